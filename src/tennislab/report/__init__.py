"""The coach-facing report (``tennislab report --out DIR``): one self-contained HTML file with its figures
embedded; see :mod:`tennislab.report.build`."""
