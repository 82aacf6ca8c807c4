"""File formats: DXF-AAMA/ASTM, RUL, canonical JSON and pattern pictures.

This package is the only place that touches pattern files; it returns model
objects and a :class:`~patternbridge.report.Report` of recoverable findings.
"""
