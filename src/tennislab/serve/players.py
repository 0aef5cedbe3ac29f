"""Player profiles: impact height and racket speed (seed 000 sec. 2.3).

The seed's three players (its refs [2] Carboch et al. 2018 and [6]
Fernandez-Fernandez et al. 2013): professional 3.0 m / 40 m/s, recreational
2.8 m / 30 m/s, junior 2.2 m / 25 m/s.  Any other profile is a
:class:`Player` (or ``register_player``).
"""

from __future__ import annotations

from dataclasses import dataclass

from tennislab.errors import InputError, check_range


@dataclass(frozen=True)
class Player:
    """A server.

    Attributes
    ----------
    name : label
    impact_height : height of the ball centre at impact [m]
    racket_speed : racket speed at the impact point [m/s]
    """

    name: str
    impact_height: float
    racket_speed: float

    def __post_init__(self):
        check_range("impact_height", self.impact_height, 0.1, 5.0, "m")
        check_range("racket_speed", self.racket_speed, 0.0, 100.0, "m/s", lo_open=True)


_PLAYERS: dict[str, Player] = {}
_ALIASES: dict[str, str] = {}


def register_player(player: Player, *aliases: str) -> Player:
    """Register a profile under its name (and aliases)."""
    _PLAYERS[player.name] = player
    for a in aliases:
        _ALIASES[a] = player.name
    return player


register_player(Player("professional", 3.0, 40.0), "pro")  # seed 000 sec. 2.3
register_player(Player("recreational", 2.8, 30.0), "rec")  # seed 000 sec. 2.3
register_player(Player("junior", 2.2, 25.0))  # seed 000 sec. 2.3

SEED_PLAYERS = ("professional", "recreational", "junior")


def player_names() -> list[str]:
    return list(_PLAYERS)


def get_player(name) -> Player:
    """A registered profile by name or alias (a :class:`Player` is returned as is)."""
    if isinstance(name, Player):
        return name
    key = _ALIASES.get(str(name).lower(), str(name).lower())
    try:
        return _PLAYERS[key]
    except KeyError:
        raise InputError(
            f"player: unknown {name!r}; choose from {', '.join(_PLAYERS)} "
            f"(aliases {', '.join(_ALIASES)}) or give --impact-height and --racket-speed"
        ) from None
