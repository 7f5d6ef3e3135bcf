"""Packaging beyond what pyproject.toml can say: the checkout's ``models/`` folder is shipped as
the package data ``vmach/models`` (``vmach.bundled`` finds it in either place), and the
polygon-shaft fixture as ``vmach/examples/polygon_shaft`` (the program ``vmach demo`` runs when
it is given none, so the demo works from a wheel)."""

from setuptools import find_packages, setup

setup(
    packages=[*find_packages(include=["vmach*", "interpreters*"]), "vmach.models",
              "vmach.examples.polygon_shaft"],
    package_dir={"vmach.models": "models", "vmach.examples.polygon_shaft": "fixtures/polygon_shaft"},
    # data files, also in folders that are not packages (vmach/checks/data/)
    package_data={"": ["*.toml", "*.json", "*.csv", "*.md", "data/*"], "vmach.models": ["*.toml"],
                  "vmach.examples.polygon_shaft": ["*.MPF", "*.SPF", "*.toml"],
                  "vmach.report": ["vendor/*", "assets/*"]},
)
