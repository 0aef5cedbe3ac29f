"""Matplotlib figures of every result (nothing here computes physics), and the words people read in
titles, tables and command output (:mod:`tennislab.plot.text`).

Importing this package loads no Matplotlib and chooses no backend: a notebook keeps its interactive
backend; the entry points that only write files (``tennislab`` on the command line, the report it
builds) choose Agg themselves.  Each figure function imports pyplot when it draws.
"""
