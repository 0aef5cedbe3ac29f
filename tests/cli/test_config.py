"""tennislab.toml and --config: flags beat the configuration, which beats the built-in defaults."""

from __future__ import annotations

import json

import pytest

from tennislab.cli import main
from tennislab.core.aero import DEFAULT_AERO
from tennislab.serve.players import get_player

FLY = ["fly", "--speed-kmh", "100", "--elevation-deg", "8", "--json"]


@pytest.fixture(autouse=True)
def _restore_player_registry():
    """Profiles registered from configuration files must not leak into other tests."""
    from tennislab.serve import players

    saved = dict(players._PLAYERS), dict(players._ALIASES)
    yield
    players._PLAYERS.clear()
    players._PLAYERS.update(saved[0])
    players._ALIASES.clear()
    players._ALIASES.update(saved[1])


def run(capsys, *args):
    try:
        rc = main(list(args))
    except SystemExit as exc:  # argparse's own errors
        rc = exc.code
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def physics(out):
    return json.loads(out)["physics"]


def test_no_configuration_gives_the_built_in_defaults(workdir, capsys):
    rc, out, err = run(capsys, *FLY)
    assert rc == 0, err
    assert physics(out)["air_density"] == pytest.approx(1.199) and physics(out)["aero"] == DEFAULT_AERO


def test_the_working_folders_file_gives_defaults_and_flags_win(workdir, capsys):
    (workdir / "tennislab.toml").write_text('[physics]\naero = "cross2014"\nair_density = 1.1\nwind = [2, 0, 0]\n')
    rc, out, err = run(capsys, *FLY)
    assert rc == 0, err
    assert physics(out)["aero"] == "cross2014"
    assert physics(out)["air_density"] == 1.1 and physics(out)["wind"] == [2.0, 0.0, 0.0]
    rc, out, _ = run(capsys, *FLY, "--air-density", "1.3", "--wind", "0", "0", "0")
    assert physics(out)["air_density"] == 1.3 and physics(out)["wind"] == [0.0, 0.0, 0.0]
    assert physics(out)["aero"] == "cross2014"
    rc, out, _ = run(capsys, "--no-config", *FLY)
    assert physics(out)["aero"] == DEFAULT_AERO


def test_config_flag_anywhere_on_the_line(workdir, capsys, tmp_path_factory):
    other = tmp_path_factory.mktemp("elsewhere") / "mine.toml"
    other.write_text("[physics]\ngravity = 9.7\n")
    for args in (["--config", str(other), *FLY], [*FLY, "--config", str(other)], [*FLY, f"--config={other}"]):
        rc, out, err = run(capsys, *args)
        assert rc == 0, err
        assert physics(out)["gravity"] == 9.7


def test_aero_table_path_is_relative_to_the_file(workdir, capsys, tmp_path_factory):
    d = tmp_path_factory.mktemp("cfg")
    rows = ["speed_ms,spin_rpm,cd,cl"] + [f"{v},{w},0.6,{0.1 + w / 1e5}" for v in (10, 50) for w in (0, 4000)]
    (d / "coeffs.csv").write_text("\n".join(rows) + "\n")
    (d / "t.toml").write_text('[physics]\naero = "table"\naero_table = "coeffs.csv"\n')
    rc, out, err = run(capsys, "--config", str(d / "t.toml"), *FLY)
    assert rc == 0, err
    assert physics(out)["aero"] == "table"


def test_court_surface_is_the_default_of_bounces_only(workdir, capsys):
    (workdir / "tennislab.toml").write_text('[court]\nsurface = "grass"\n')
    rc, out, err = run(capsys, *FLY)
    assert rc == 0, err  # a configured surface is not an ignored flag
    rc, out, _ = run(capsys, *FLY, "--bounces", "1")
    assert json.loads(out)["surface"] == "grass"
    rc, out, _ = run(capsys, *FLY, "--bounces", "1", "--surface", "clay")
    assert json.loads(out)["surface"] == "clay"


@pytest.mark.parametrize(
    "text,expect",
    [
        ("[physics]\nmass = 5\n", "tennislab.toml: physics.mass: 5 kg is outside the allowed range"),
        ("[physics]\naero = 'nope'\n", "tennislab.toml: physics.aero: unknown"),
        ("[physics]\nmas = 1\n", "tennislab.toml: physics.mas: unknown key (did you mean mass?)"),
        ("[court]\nsurface = 'ice'\n", "tennislab.toml: court.surface"),
        ("[players.me]\nimpact_height = 2\n", "players.me.racket_speed: missing"),
        ("[players.me]\nimpact_height = 2\nracket_speed = 30\nspeed = 1\n", "players.me.speed: unknown key"),
        ("[players.me]\nimpact_height = 9\nracket_speed = 30\n", "players.me.impact_height: 9 m is outside"),
        ("[defaults]\nmachine = 'club'\n", "defaults.machine: no [machines.club] table"),
        ("[defaults]\nplayer = 'nobody'\n", "defaults.player: 'nobody' is neither"),
        ("[physics\n", "tennislab.toml: not valid TOML"),
    ],
)
def test_bad_configuration_is_one_line_naming_the_key(workdir, capsys, text, expect):
    (workdir / "tennislab.toml").write_text(text)
    rc, out, err = run(capsys, *FLY)
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err and expect in err, err


def test_missing_config_file(workdir, capsys):
    rc, _, err = run(capsys, "--config", "nope.toml", *FLY)
    assert rc == 2 and err.strip() == "tennislab: error: --config: nope.toml: no such file"


def test_help_works_with_a_broken_configuration(workdir, capsys):
    (workdir / "tennislab.toml").write_text("[physics\n")
    rc, out, _ = run(capsys, "fly", "--help")
    assert rc == 0 and "--config FILE" in out and "--spin-axis" in out


def test_player_profiles_reach_every_player_flag(workdir, capsys):
    (workdir / "tennislab.toml").write_text(
        "[defaults]\nplayer = 'Ana'\n[players.Ana]\nimpact_height = 2.55\nracket_speed = 31\n"
    )
    rc, out, err = run(capsys, "serve", "--impact-angle", "9", "--face-angle", "6", "--json")
    assert rc == 0, err
    assert json.loads(out)["player"] == "Ana"
    assert get_player("ana").racket_speed == 31.0
    rc, out, err = run(capsys, "serve", "--player", "junior", "--impact-angle", "9", "--face-angle", "6", "--json")
    assert json.loads(out)["player"] == "junior"


def test_player_file_on_a_player_flag(workdir, capsys):
    (workdir / "bo.toml").write_text("impact_height = 2.4\nracket_speed = 28\n")
    rc, out, err = run(capsys, "serve", "--player", "bo.toml", "--impact-angle", "9", "--face-angle", "6", "--json")
    assert rc == 0, err
    assert json.loads(out)["player"] == "bo"


def test_machine_profiles(workdir, capsys):
    (workdir / "tennislab.toml").write_text(
        "[machines.club]\nposition = [-12, 1.5]\nroller_radius = 0.12\n"
        "[machines.home]\nposition = [-11, 0]\n[defaults]\nmachine = 'club'\n"
    )
    aim = ["launcher", "aim", "--target", "9", "2", "--speed-kmh", "80", "--json"]

    def machine(*extra):
        rc, out, err = run(capsys, *aim, *extra)
        assert rc == 0, err
        return json.loads(out)["machine"]

    assert machine()["position"] == [-12.0, 1.5] and machine()["roller_radius_m"] == 0.12
    assert machine("--machine", "home")["position"] == [-11.0, 0.0]
    assert machine("--machine-position", "-12.5", "0")["position"] == [-12.5, 0.0]
    rc, _, err = run(capsys, *aim, "--machine", "gym")
    assert rc == 2 and "--machine: no profile 'gym' in tennislab.toml (profiles: club, home)" in err


def test_example_configuration_is_valid(capsys):
    from pathlib import Path

    example = Path(__file__).resolve().parents[2] / "examples" / "tennislab.toml"
    rc, out, err = run(capsys, "--config", str(example), *FLY)
    assert rc == 0, err
