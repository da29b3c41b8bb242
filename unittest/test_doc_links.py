"""Relative links of the user docs resolve: README.md, doc/*.md, doc/*.rst, bench/README.md and the
examples' READMEs.  Markdown links [text](target) and reStructuredText links `text <target>`_ (or
__) that are not URLs must name an existing file or folder, and a #anchor into a Markdown file must
match one of its headings (GitHub's rule: lower case, punctuation other than - and _ dropped, spaces
to -).  Fails listing each broken link with its file and line.
Usage: python3 test_doc_links.py [SOURCE_DIR]   (default: the folder above this file)"""
import glob
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
files = [os.path.join(root, "README.md"), os.path.join(root, "bench", "README.md")]
files += sorted(glob.glob(os.path.join(root, "doc", "*.md")) + glob.glob(os.path.join(root, "doc", "*.rst")))
files += sorted(glob.glob(os.path.join(root, "examples", "*", "README.md")))

MD_LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
RST_LINK = re.compile(r"`[^`<]*<([^>`]+)>`__?")
FENCE = re.compile(r"^\s*```")
_anchors = {}


def anchors(path):
    """the GitHub anchors of the headings of a Markdown file"""
    if path not in _anchors:
        seen, out, fenced = {}, set(), False
        with open(path) as f:
            for line in f:
                if FENCE.match(line):
                    fenced = not fenced
                m = None if fenced else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
                if not m:
                    continue
                a = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
                n = seen.get(a, 0)
                seen[a] = n + 1
                out.add(a if n == 0 else f"{a}-{n}")
        _anchors[path] = out
    return _anchors[path]


errors, nlinks = [], 0
for path in files:
    if not os.path.exists(path):
        continue
    text = open(path).read()
    # join the lines of a reST link broken across lines
    links = []
    pattern = RST_LINK if path.endswith(".rst") else MD_LINK
    for m in pattern.finditer(text):
        links.append((text.count("\n", 0, m.start()) + 1, m.group(1).strip()))
    for line, target in links:
        if re.match(r"[a-z]+:", target) or target.startswith("mailto:"):
            continue
        nlinks += 1
        file_part, _, anchor = target.partition("#")
        dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
        rel = os.path.relpath(path, root)
        if not os.path.exists(dest):
            errors.append(f"{rel}:{line}: {target}: no such file")
        elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
            errors.append(f"{rel}:{line}: {target}: no heading with anchor #{anchor} in {os.path.relpath(dest, root)}")

if errors:
    print("\n".join(errors))
    sys.exit(1)
print(f"{nlinks} relative links in {len(files)} files resolve")
