#!/usr/bin/env python3
"""Every relative link in the project's Markdown resolves: the file exists and, with
#anchor, the file has a heading of that anchor (GitHub's rule: lower case, punctuation
dropped but hyphens and underscores, spaces to hyphens; a repeated heading gets -1, -2).
Prints one line per broken link and exits 1 when there is one.

usage: check_links.py SOURCE_DIR
"""
import os
import re
import sys

LINK = re.compile(r"(?<!\!)\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)|!\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def slug(heading):
    text = re.sub(r"`([^`]*)`", r"\1", heading.strip())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link's text
    text = text.lower()
    text = re.sub(r"[^\w\- ]", "", text, flags=re.UNICODE)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        found, counts, fenced = set(), {}, False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if FENCE.match(line):
                    fenced = not fenced
                    continue
                m = None if fenced else re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
                if not m:
                    continue
                base = slug(m.group(2))
                n = counts.get(base, 0)
                counts[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
        cache[path] = found
    return cache[path]


def markdown_files(root):
    skip = {".git", "build", "results", "node_modules"}
    for top, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in skip and not d.startswith("build")]
        for name in files:
            if name.endswith(".md"):
                yield os.path.join(top, name)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    broken = 0
    checked = 0
    for md in sorted(markdown_files(root)):
        fenced = False
        with open(md, encoding="utf-8") as f:
            lines = f.readlines()
        for number, line in enumerate(lines, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if fenced:
                continue
            for m in LINK.finditer(line):
                target = m.group(1) or m.group(2)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                    continue
                checked += 1
                file_part, _, anchor = target.partition("#")
                path = md if not file_part else os.path.normpath(os.path.join(os.path.dirname(md), file_part))
                where = f"{os.path.relpath(md, root)}:{number}"
                if not os.path.exists(path):
                    print(f"{where}: link to a missing file: {target}")
                    broken += 1
                elif anchor and path.endswith(".md") and anchor not in anchors(path):
                    print(f"{where}: no heading '#{anchor}' in {os.path.relpath(path, root)}")
                    broken += 1
    print(f"{checked} links checked, {broken} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
