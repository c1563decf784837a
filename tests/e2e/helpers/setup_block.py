#!/usr/bin/env python3
"""Prints the editor setup block NAME of a markdown file, verbatim but for the
placeholder /path/to/gloc, replaced by the repository's path: the end-to-end tests
load a guide's setup text exactly as a reader copies it.

A block is the fenced code block right after the line `<!-- setup: NAME -->`.
Usage: setup_block.py FILE.md NAME REPO > setup.el
"""
import sys


def block(markdown: str, name: str) -> str:
    lines = markdown.splitlines()
    marker = f"<!-- setup: {name} -->"
    try:
        start = lines.index(marker)
    except ValueError:
        raise SystemExit(f"no `{marker}` in the guide")
    fence = start + 1
    if fence >= len(lines) or not lines[fence].startswith("```"):
        raise SystemExit(f"`{marker}` is not followed by a code block")
    body = []
    for line in lines[fence + 1:]:
        if line.startswith("```"):
            return "\n".join(body) + "\n"
        body.append(line)
    raise SystemExit(f"the code block after `{marker}` is not closed")


if __name__ == "__main__":
    path, name, repo = sys.argv[1:4]
    with open(path, encoding="utf-8") as file:
        text = block(file.read(), name)
    sys.stdout.write(text.replace("/path/to/gloc", repo))
