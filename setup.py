"""The one build step pyproject.toml does not state: the TF buffer's optional C module.

``optional=True``: without a C compiler the install still succeeds and zenros.tf runs the
same code in Python (see docs/tf.md, "The compiled hot paths").
"""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "zenros.tf._speedups",
            sources=["shared/tf/_speedups.c"],
            optional=True,
            # -ffp-contract=off: no fused multiply-adds, so results round as Python's do
            extra_compile_args=["-O2", "-ffp-contract=off"],
        )
    ]
)
