"""``tennislab material``: ball material parameters from test tables (Wójcicki, Puciłowski & Kulesza 2010, section 5).

``young --csv FILE``: Young's modulus per row from a load-deformation table
(columns ``load_n`` or ``load_kg``, ``deformation_m``), its mean and the slope
modulus; ``friction --csv FILE``: friction coefficient mu = tan(eta) per row
(column ``friction_angle_deg``, optional ``contact_length_m``) and the mean.
No flight is computed here, so the physics flags of ``fly`` are not accepted.
"""

from __future__ import annotations

from tennislab.cli.common import emit_json
from tennislab.errors import check_range
from tennislab.io.material_csv import read_friction_angles, read_load_deformation
from tennislab.launcher.machine import PAPER
from tennislab.launcher.materials import SEED_BALL_RADIUS, SEED_CONTACT_AREA, friction_coefficient, young_modulus


def register(sub) -> None:
    p = sub.add_parser(
        "material",
        help=f"Young's modulus and friction coefficient from test tables ({PAPER})",
        description=f"Ball material parameters from test tables ({PAPER}, section 5).",
    )
    ms = p.add_subparsers(dest="material_command", metavar="SUBCOMMAND", parser_class=type(p))
    ms.required = True
    y = ms.add_parser("young", help="Young's modulus E = F 2r / (s dl) from a load-deformation CSV")
    y.add_argument("--csv", required=True, metavar="FILE", help="CSV with load_n (or load_kg) and deformation_m")
    y.add_argument(
        "--diameter",
        type=float,
        default=None,
        help=f"ball diameter 2r [m] (default: 2 x --radius if given, else the paper's {2 * SEED_BALL_RADIUS:g})",
    )
    y.add_argument("--radius", type=float, default=None, help="ball radius r [m] (instead of --diameter)")
    y.add_argument(
        "--contact-area-m2",
        type=float,
        default=None,
        help="contact area s [m^2] (default 2.12e-4, implied by the paper's Tables 1-2)",
    )
    y.add_argument("--json", action="store_true", help="print one JSON object")
    y.set_defaults(func=run_young)
    f = ms.add_parser("friction", help="friction coefficient mu = tan(eta) from friction angles")
    f.add_argument("--csv", required=True, metavar="FILE", help="CSV with friction_angle_deg [, contact_length_m]")
    f.add_argument("--json", action="store_true", help="print one JSON object")
    f.set_defaults(func=run_friction)


def run_young(args) -> int:
    load, dl = read_load_deformation(args.csv)
    if args.diameter is not None:
        diameter = args.diameter
    elif args.radius is not None:
        diameter = 2 * check_range("radius", args.radius, 0, 0.1, "m", lo_open=True)
    else:
        diameter = 2 * SEED_BALL_RADIUS
    area = SEED_CONTACT_AREA if args.contact_area_m2 is None else args.contact_area_m2
    res = young_modulus(load, dl, diameter, area)
    out = res.to_dict()
    if args.json:
        emit_json(out)
        return 0
    print(f"{'load [N]':>10} {'dl [mm]':>9} {'E [MPa]':>9}")
    for r in out["rows"]:
        print(f"{r['load_n']:10.2f} {r['deformation_m'] * 1e3:9.2f} {r['young_modulus_mpa']:9.2f}")
    print(
        f"mean {out['mean_mpa']:.2f} MPa (min {out['min_mpa']:.2f}, max {out['max_mpa']:.2f}, "
        f"range {out['range_mpa']:.2f}); slope fit {out['slope_modulus_mpa']:.2f} MPa "
        f"[s = {area:.3g} m^2, 2r = {diameter:g} m]"
    )
    return 0


def run_friction(args) -> int:
    ang, cl = read_friction_angles(args.csv)
    res = friction_coefficient(ang, cl)
    out = res.to_dict()
    if args.json:
        emit_json(out)
        return 0
    for r in out["rows"]:
        extra = f"  contact {r['contact_length_m'] * 1e3:.0f} mm" if "contact_length_m" in r else ""
        print(f"eta {r['friction_angle_deg']:5.1f} deg -> mu {r['friction_coefficient']:.3f}{extra}")
    print(f"mean mu {out['mean']:.3f}, max {out['max']:.3f}")
    return 0
