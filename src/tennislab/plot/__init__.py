"""Matplotlib figures (Agg backend; nothing here computes physics)."""

import matplotlib

matplotlib.use("Agg")
