"""Reproduction report: claims of the paper, figures, and their rendering (md, html, json)."""
