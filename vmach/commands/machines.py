"""``vmach machines``: the bundled machine models, one line each, from their own metadata
(``name``, ``description``, ``formula``, ``[control] dialect``, ``[[axes]]``)."""

from __future__ import annotations

import argparse
import json
import tomllib
from pathlib import Path
from typing import Any

from vmach.bundled import MODELS_DIR, model_files

HELP = "list the bundled machine models, one line each"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--format", choices=("text", "json"), default="text")


def describe(path: Path) -> dict[str, Any]:
    """One model file's metadata: name (``--machine`` takes it), description, structure
    formula (None for a model written as links and joints), dialect (None: by the program's
    extension), axes (without ``[[axes]]``: the formula's letters in X Y Z A B C order); a file
    that does not parse is listed with ``error`` (``vmach check --machine`` says where)."""
    entry: dict[str, Any] = {"name": path.stem, "file": path.name}
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        return {**entry, "error": str(exc).split(" (at")[0]}
    control = raw.get("control") if isinstance(raw.get("control"), dict) else {}
    axes = raw.get("axes") if isinstance(raw.get("axes"), list) else []
    entry.update(
        description=str(raw.get("description", "")),
        formula=raw.get("formula") if isinstance(raw.get("formula"), str) else None,
        dialect=control.get("dialect") if isinstance(control.get("dialect"), str) else None,
        axes=[str(a.get("name")) for a in axes if isinstance(a, dict) and "name" in a],
    )
    if not entry["axes"] and entry["formula"]:      # without [[axes]]: the formula's letters
        entry["axes"] = sorted({c for c in entry["formula"] if c in "XYZABC"}, key="XYZABC".index)
    return entry


def run(args: argparse.Namespace) -> int:
    models = [describe(p) for p in model_files()]
    if args.format == "json":
        print(json.dumps({"folder": str(MODELS_DIR), "models": models}, indent=2, ensure_ascii=False))
        return 0
    if not models:
        print(f"no machine models in {MODELS_DIR}")
        return 0
    width = max(len(m["name"]) for m in models)
    for m in models:
        if "error" in m:
            print(f"{m['name']:<{width}}  (unreadable: {m['error']})")
            continue
        axes = " ".join(m["axes"]) or "-"
        print(f"{m['name']:<{width}}  {m['dialect'] or 'any':<9}  {axes:<14}  {m['description']}")
    print(f"\n{len(models)} model(s) in {MODELS_DIR}; use one with --machine NAME (docs/getting-started.md)")
    return 0
