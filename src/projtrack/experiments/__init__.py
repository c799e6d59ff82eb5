"""The papers' experiments: the studies the book's notebooks run.

The top layer of the package. Each module here combines a synthetic scene from
:mod:`projtrack.scenes`, the algorithms of a topic package (:mod:`projtrack.hough`,
:mod:`projtrack.jpda`, ...) and the metrics and tables of a paper's figure or table, and,
beside them, the plotting helpers that draw them. Notebooks call these functions and keep
the narrative, the calls and the figures; a reader who wants to rerun a study at another
size imports it from here.

One subpackage per topic, imported on demand (``from projtrack.experiments import hough``).
"""
