"""Packaging beyond what pyproject.toml can say: the checkout's ``models/`` folder is shipped as
the package data ``vmach/models`` (``vmach.bundled`` finds it in either place)."""

from setuptools import find_packages, setup

setup(
    packages=[*find_packages(include=["vmach*", "interpreters*"]), "vmach.models"],
    package_dir={"vmach.models": "models"},
    package_data={"*": ["*.toml", "*.json", "*.csv"], "vmach.models": ["*.toml"],
                  "vmach.report": ["vendor/*.js", "vendor/LICENSE*", "vendor/*.md", "assets/*"]},
)
