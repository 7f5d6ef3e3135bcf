"""Packaging beyond what pyproject.toml can say: the checkout's ``models/`` folder is shipped as
the package data ``vmach/models`` (``vmach.bundled`` finds it in either place)."""

from setuptools import find_packages, setup

setup(
    packages=[*find_packages(include=["vmach*", "interpreters*"]), "vmach.models"],
    package_dir={"vmach.models": "models"},
    # data files, also in folders that are not packages (vmach/checks/data/)
    package_data={"": ["*.toml", "*.json", "*.csv", "*.md", "data/*"], "vmach.models": ["*.toml"],
                  "vmach.report": ["vendor/*", "assets/*"]},
)
