"""Where the bundled machine models are: ``models/`` of a source checkout, or the package
data ``vmach/models/`` of an installed wheel (``setup.py`` maps the one onto the other)."""

from __future__ import annotations

from pathlib import Path

_HERE = Path(__file__).resolve().parent


def _models_dir() -> Path:
    """The installed package's ``vmach/models`` when there is one, else the checkout's
    ``models/`` beside the package (an editable install reads the files where they are)."""
    installed = _HERE / "models"
    if installed.is_dir():
        return installed
    return _HERE.parent / "models"


#: the folder of the bundled models (``*.toml``)
MODELS_DIR: Path = _models_dir()


def model_files() -> list[Path]:
    """The bundled model files, sorted by name."""
    return sorted(MODELS_DIR.glob("*.toml"))
