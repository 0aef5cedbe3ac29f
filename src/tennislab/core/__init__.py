"""Pure physics on SI floats and NumPy arrays: no I/O, no plotting, no CLI.

Modules: :mod:`ball`, :mod:`atmosphere`, :mod:`court`, :mod:`aero` (model
registry), :mod:`flight` (one right-hand side; SciPy dense path and Numba
batch path), :mod:`integrators` (the compiled Dormand-Prince kernel with
event location).
"""
