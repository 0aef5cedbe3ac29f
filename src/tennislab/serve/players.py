"""Player profiles: who serves (impact height and racket speed), registered by name.

The paper's three players (Grosen, Kousted & Treichel 2021, sec. 2.3, after its refs [2]
Carboch et al. 2018 and [6] Fernandez-Fernandez et al. 2013): professional 3.0 m / 40 m/s,
recreational 2.8 m / 30 m/s, junior 2.2 m / 25 m/s.  Any other player is a
:class:`PlayerProfile`, built in code or from a plain dict (a user's config file:
:meth:`PlayerProfile.from_dict`) and registered with :func:`register_player`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from tennislab.errors import InputError, check_range


@dataclass(frozen=True)
class PlayerProfile:
    """A server.

    Attributes
    ----------
    name : label (registry key, lower case)
    impact_height : height of the ball centre at impact [m] (0.1-5)
    racket_speed : racket speed at the impact point [m/s] (0-100, > 0)
    description : free text (e.g. where the numbers come from) [-]
    aliases : other names the registry accepts (e.g. ``("pro",)``) [-]
    """

    name: str
    impact_height: float
    racket_speed: float
    description: str = ""
    aliases: tuple[str, ...] = ()

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError("name: a player needs a non-empty name")
        check_range("impact_height", self.impact_height, 0.1, 5.0, "m")
        check_range("racket_speed", self.racket_speed, 0.0, 100.0, "m/s", lo_open=True)
        object.__setattr__(self, "impact_height", float(self.impact_height))
        object.__setattr__(self, "racket_speed", float(self.racket_speed))
        object.__setattr__(self, "aliases", tuple(str(a) for a in self.aliases))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> PlayerProfile:
        """A profile from a plain dict with the field names of this class (a config file's player
        table): ``name``, ``impact_height`` [m], ``racket_speed`` [m/s], optional ``description``,
        ``aliases`` (list of names).  Unknown keys and missing required keys are refused."""
        if not isinstance(d, dict):
            raise InputError(f"player: expected a table of fields, got {type(d).__name__}")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names)
        if unknown:
            raise InputError(f"{unknown[0]}: unknown player field; allowed: {', '.join(sorted(names))}")
        missing = [k for k in ("name", "impact_height", "racket_speed") if k not in d]
        if missing:
            raise InputError(f"{missing[0]}: missing in the player table")
        kw = dict(d)
        for k in ("impact_height", "racket_speed"):
            if isinstance(kw[k], bool) or not isinstance(kw[k], (int, float)):
                raise InputError(f"{k}: expected a number, got {kw[k]!r}")
        aliases = kw.get("aliases", ())
        if isinstance(aliases, str) or not isinstance(aliases, (list, tuple)):
            raise InputError("aliases: expected a list of names")
        kw["aliases"] = tuple(aliases)
        return cls(**kw)

    def to_dict(self) -> dict:
        """The profile as a plain dict (the same fields :meth:`from_dict` reads)."""
        return {
            "name": self.name,
            "impact_height": self.impact_height,
            "racket_speed": self.racket_speed,
            "description": self.description,
            "aliases": list(self.aliases),
        }

    def with_overrides(self, impact_height: float | None = None, racket_speed: float | None = None) -> PlayerProfile:
        """This profile with a different impact height [m] and/or racket speed [m/s] (name marked ``*``)."""
        if impact_height is None and racket_speed is None:
            return self
        return PlayerProfile(
            f"{self.name}*",
            self.impact_height if impact_height is None else impact_height,
            self.racket_speed if racket_speed is None else racket_speed,
            self.description,
        )


_PLAYERS: dict[str, PlayerProfile] = {}
_ALIASES: dict[str, str] = {}


def register_player(player: PlayerProfile | dict, *aliases: str) -> PlayerProfile:
    """Register a profile (or a plain dict, :meth:`PlayerProfile.from_dict`) under its name and aliases;
    a later registration of the same name replaces the earlier one."""
    if isinstance(player, dict):
        player = PlayerProfile.from_dict(player)
    key = player.name.lower()
    _PLAYERS[key] = player
    for a in (*player.aliases, *aliases):
        _ALIASES[a.lower()] = key
    return player


SEED_SOURCE = "Grosen, Kousted & Treichel 2021, sec. 2.3 (after Carboch et al. 2018; Fernandez-Fernandez et al. 2013)"
register_player(PlayerProfile("professional", 3.0, 40.0, SEED_SOURCE, ("pro",)))
register_player(PlayerProfile("recreational", 2.8, 30.0, SEED_SOURCE, ("rec",)))
register_player(PlayerProfile("junior", 2.2, 25.0, SEED_SOURCE))

#: The paper's three players, in its order.
SEED_PLAYERS = ("professional", "recreational", "junior")


def player_names() -> list[str]:
    """Registered profile names (the paper's players first)."""
    return list(_PLAYERS)


def get_player(name) -> PlayerProfile:
    """A registered profile by name or alias (a :class:`PlayerProfile` is returned as is)."""
    if isinstance(name, PlayerProfile):
        return name
    key = _ALIASES.get(str(name).lower(), str(name).lower())
    try:
        return _PLAYERS[key]
    except KeyError:
        raise InputError(
            f"player: unknown {name!r}; choose from {', '.join(_PLAYERS)} "
            f"(aliases {', '.join(_ALIASES)}) or give an impact height and racket speed"
        ) from None
