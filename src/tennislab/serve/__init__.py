"""Serve analysis (seed 000): player profiles, the alpha x beta serve window, the
reproduction of the seed's Table 1, Monte Carlo margins of error and 3-D serves."""

from tennislab.serve.players import Player, get_player, player_names, register_player
from tennislab.serve.setup import SeedCriteria, seed_flight_params, seed_impact_params

__all__ = [
    "Player",
    "get_player",
    "player_names",
    "register_player",
    "SeedCriteria",
    "seed_flight_params",
    "seed_impact_params",
]
