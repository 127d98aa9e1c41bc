"""The build steps pyproject.toml does not state: package discovery and the TF C module.

Packages are found under shared/ and services/ (pyproject maps them to zenros and
zenros.services), so a new subpackage is installed without editing a list. ``zenros.deploy``
is deploy/ as data: its launch files and the demo map (pyproject's package-data), so an
installed zenros carries them where a checkout has them (``zenros.launch.files``).

``optional=True``: without a C compiler the install still succeeds and zenros.tf runs the
same code in Python (see docs/tf.md, "The compiled hot paths").
"""

from setuptools import Extension, find_packages, setup


def _packages() -> list[str]:
    """Every package under shared/ (as zenros.*) and services/ (as zenros.services.*), and
    deploy/ (zenros.deploy, data only)."""
    found = ["zenros", "zenros.services", "zenros.deploy"]
    found += [f"zenros.{p}" for p in find_packages("shared")]
    found += [f"zenros.services.{p}" for p in find_packages("services")]
    return found


setup(
    packages=_packages(),
    ext_modules=[
        Extension(
            "zenros.tf._speedups",
            sources=["shared/tf/_speedups.c"],
            optional=True,
            # -ffp-contract=off: no fused multiply-adds, so results round as Python's do
            extra_compile_args=["-O2", "-ffp-contract=off"],
        ),
        Extension(
            "zenros.services.nav.costmap._edt",
            sources=["services/nav/costmap/_edt.c"],
            optional=True,  # without it inflation runs its numpy reference (docs/nav-planner.md)
            extra_compile_args=["-O2"],
        ),
        Extension(
            "zenros.services.nav.planning._astar",
            sources=["services/nav/planning/_astar.c"],
            optional=True,  # without it the planner runs its Python reference (docs/nav-planner.md)
            extra_compile_args=["-O2", "-ffp-contract=off"],
        ),
        Extension(
            "zenros.services.chassis._march",
            sources=["services/chassis/_march.c"],
            optional=True,  # without it the laser runs its numpy reference (docs/chassis.md)
            extra_compile_args=["-O2"],
        ),
    ]
)
