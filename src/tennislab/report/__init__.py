"""The coach-facing HTML report (``tennislab report --out DIR``); see :mod:`tennislab.report.build`."""
