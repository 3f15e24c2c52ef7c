#!/usr/bin/python3
"""Every relative link of the documentation resolves: the file exists, and an #anchor names a
heading of the file it points into (GitHub's rule: lower case, punctuation dropped, spaces to
hyphens).  Checks README.md, BENCHMARKS.md, CHANGELOG.md and docs/*.md.

    check_links.py SOURCE_DIR
"""
import glob
import os
import re
import sys

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^```.*?^```", re.S | re.M)


def slug(heading):
    text = re.sub(r"[`*_]", "", heading.strip()).lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    text = FENCE.sub("", open(path, encoding="utf-8").read())
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6} (.+)$", text, re.M)}


def broken_links(root):
    pages = ["README.md", "BENCHMARKS.md", "CHANGELOG.md"] + sorted(
        os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "docs", "*.md")))
    problems = []
    for page in pages:
        path = os.path.join(root, page)
        if not os.path.exists(path):
            problems.append(f"{page}: missing")
            continue
        text = FENCE.sub("", open(path, encoding="utf-8").read())
        for m in LINK.finditer(text):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            line = text[:m.start()].count("\n") + 1
            if not os.path.exists(dest):
                problems.append(f"{page}:{line}: {target}: no such file")
            elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                problems.append(f"{page}:{line}: {target}: no heading with anchor #{anchor}")
    return pages, problems


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    pages, problems = broken_links(root)
    for p in problems:
        print(p)
    print(f"{len(pages)} pages checked, {len(problems)} broken links")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
