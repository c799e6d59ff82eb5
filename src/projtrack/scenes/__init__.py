"""Generators of the synthetic data that stands in for data the papers used but did not publish.

Each submodule documents what it makes and which paper it serves; import the one you
need, e.g. ``from projtrack.scenes import letters``. Every generator takes an explicit
``numpy.random.Generator`` (``rng=``) where it draws anything, and none is tuned to hit a
number reported by a paper.
"""
