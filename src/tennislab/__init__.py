"""tennislab: the physics of a tennis ball.

Racket-ball impact, 3-D flight with drag and Magnus lift, bounce on the court,
Hawk-Eye-style line calling and two-roller ball launchers.  SI units inside;
see ``docs/conventions.md`` for the coordinate frame.
"""

from tennislab.errors import InputError, TennisLabError

__version__ = "0.1.0"
__all__ = ["TennisLabError", "InputError", "__version__"]
