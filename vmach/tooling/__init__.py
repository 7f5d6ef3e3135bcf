"""Cutting tools: profiles, libraries (``--tools FILE.toml``), revolved solids.

    lib = load_tools("fixtures/polygon_shaft/tools.toml")
    tool = lib.lookup("GLOD D40")          # or lib.lookup(1) / lib.lookup("1")
    solid = tool_solid(tool)               # convex pieces in the tool frame, cached
"""

from vmach.tooling.library import ToolLibrary, load_tools, parse_tools
from vmach.tooling.model import KINDS, Offset, Tool
from vmach.tooling.solid import ToolSolid, frames, place, segments_for, tool_solid

__all__ = [
    "KINDS", "Offset", "Tool", "ToolLibrary", "ToolSolid", "frames", "load_tools",
    "parse_tools", "place", "segments_for", "tool_solid",
]
