"""Pure physics on SI floats and NumPy arrays: no I/O, no plotting, no CLI.

Modules: :mod:`ball`, :mod:`atmosphere`, :mod:`court`, :mod:`aero` (model
registry), :mod:`events` (the flight events both paths read, the batch
table's columns and status codes), :mod:`flight` (one right-hand side; SciPy
dense path and Numba batch path), :mod:`integrators` (the compiled
Dormand-Prince kernel with event location), :mod:`surfaces` and
:mod:`bounce` (court impact), :mod:`_jit` (the Numba options of every kernel).
"""
