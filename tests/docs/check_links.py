#!/usr/bin/env python3
"""Every link in the README and the guide resolves: a relative link names a file or folder of the
repository (or of ../shared, the workspace's design notes), and a #fragment names a heading of
the file it points into (GitHub's slugs). Links to the web are not fetched (CI has no network to
spare): only their form is checked. usage: check_links.py SOURCE_DIR"""
import glob
import os
import re
import sys

src = sys.argv[1]
files = [os.path.join(src, "README.md"), os.path.join(src, "protocol", "PROTOCOL.md")] + \
    sorted(glob.glob(os.path.join(src, "docs", "*.md")))
LINK = re.compile(r"(?<!\!)\[[^\]]*\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)")


def slugs(path):
    out = set()
    in_code = False
    with open(path) as f:
        for line in f:
            if line.startswith("```"):
                in_code = not in_code
            if in_code or not line.startswith("#"):
                continue
            title = line.lstrip("#").strip().lower()
            title = re.sub(r"[^\w\- ]", "", title)
            out.add(title.replace(" ", "-"))
    return out


bad, n = [], 0
for f in files:
    text = open(f).read()
    text = re.sub(r"```.*?```", "", text, flags=re.S)  # links in code blocks are examples
    for m in LINK.finditer(text):
        target = m.group(1) or m.group(2)
        n += 1
        if re.match(r"^[a-z]+://", target) or target.startswith("mailto:"):
            if not re.match(r"^https?://[\w.-]+", target):
                bad.append((f, target, "a malformed address"))
            continue
        path, _, frag = target.partition("#")
        dest = os.path.normpath(os.path.join(os.path.dirname(f), path)) if path else f
        if not os.path.exists(dest):
            bad.append((f, target, "no such file"))
            continue
        if frag and dest.endswith(".md") and frag not in slugs(dest):
            bad.append((f, target, "no such heading"))
for f, t, why in bad:
    print(f"FAIL: {os.path.relpath(f, src)}: ({t}): {why}")
print(f"links: {n} checked in {len(files)} files, {len(bad)} broken")
sys.exit(1 if bad else 0)
