"""Exporters that turn a performance into files: BVH motion and the stand-alone avatar page."""

from agent.export.bvh import bvh_text, write_bvh
from agent.export.html import ViewerNotBuiltError, render_html, write_html

__all__ = ["ViewerNotBuiltError", "bvh_text", "render_html", "write_bvh", "write_html"]
