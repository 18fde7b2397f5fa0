# SPDX-License-Identifier: MIT
"""The documentation speaks to users (ctest docs.pages).

    python3 tests/scripts/test_docs.py SOURCE_DIR

1. No workshop words: user pages, error messages, comments and tests cite sources by author and
   year (docs/references.md), never the project's own notes ("seed digest", "thesis A",
   "accuracy-reference"), issue numbers, branch names or files of a shared folder users do not
   have. Checked in README.md, docs/, core/, plugins/, scripting/, scripts/ and tests/.
2. Every relative link of docs/ and README.md reaches an existing file, and a `#anchor` a heading
   of the page it points to.
3. A user page carries no measurement log: the dated sessions live under docs/results/.
"""
import os
import re
import sys

src = sys.argv[1]
failures = []

# Built from pieces so that this file does not match itself.
WORDS = re.compile("|".join([
    r"seed" + r" digest", r"seed-" + r"digest", r"\b[Tt]hesis [AB]\b", r"\b[Tt]hesis-[AB]\b",
    r"\b[Ii]ssue [0-9]+", r"\bH[0-9]'s branch", r"\bB3[ab]\b", r"rockfall-" + r"inputs",
    r"accuracy-" + r"reference", r"bodies-bonds-" + r"rockfall", r"integration-" + r"notes",
    r"\.\./shared/", r"shared/(?:reference|design|repro|anchors)", r"design/lua-" + r"api",
    r"thesis-" + r"era",
]))
SKIP_FILES = {"tests/scripts/test_docs.py"}
SKIP_DIRS = ()
TEXT = (".md", ".lua", ".cpp", ".hpp", ".h", ".py", ".sh", ".cmake", ".txt", ".in")


def files():
    yield "README.md"
    for top in ("docs", "core", "plugins", "scripting", "scripts", "tests"):
        for root, _, names in os.walk(os.path.join(src, top)):
            for n in sorted(names):
                rel = os.path.relpath(os.path.join(root, n), src)
                if n.endswith(TEXT) or n == "CMakeLists.txt":
                    yield rel


hits = 0
for rel in files():
    if rel in SKIP_FILES or rel.startswith(SKIP_DIRS):
        continue
    with open(os.path.join(src, rel), encoding="utf-8", errors="replace") as f:
        for k, line in enumerate(f, 1):
            m = WORDS.search(line)
            if m:
                hits += 1
                if hits <= 40:
                    print(f"{rel}:{k}: workshop words '{m.group(0)}': {line.strip()[:120]}")
if hits:
    failures.append(f"{hits} line(s) with workshop words")


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    h = heading.strip().lower()
    h = re.sub(r"[`*_]", "", h)
    h = re.sub(r"[^\w\- ]", "", h)
    return h.replace(" ", "-")


def anchors(path):
    out, fence = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fence = not fence
            elif not fence and line.startswith("#"):
                out.add(slug(line.lstrip("#")))
    return out


LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
pages = ["README.md"] + [os.path.relpath(os.path.join(r, n), src)
                         for r, _, ns in os.walk(os.path.join(src, "docs")) for n in ns
                         if n.endswith(".md")]
bad = 0
for rel in sorted(pages):
    if rel in SKIP_FILES:
        continue
    path = os.path.join(src, rel)
    text = open(path, encoding="utf-8").read()
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    for target in LINK.findall(text):
        if re.match(r"[a-z]+://|mailto:", target):
            continue
        file_part, _, anchor = target.partition("#")
        dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part \
            else path
        if not os.path.exists(dest):
            bad += 1
            print(f"{rel}: link to a missing file: {target}")
        elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
            bad += 1
            print(f"{rel}: link to a missing heading: {target}")
if bad:
    failures.append(f"{bad} broken link(s)")

logs = 0
for rel in sorted(pages):
    if rel.startswith("docs/results/") or rel in SKIP_FILES:
        continue
    for k, line in enumerate(open(os.path.join(src, rel), encoding="utf-8"), 1):
        if re.match(r"#+ .*\b[Ss]ession\b", line) or re.match(r"Session `\d{8}T", line):
            logs += 1
            print(f"{rel}:{k}: a measurement session on a user page: {line.strip()[:100]}")
if logs:
    failures.append(f"{logs} measurement session(s) on user pages (move them to docs/results/)")

if failures:
    print("FAIL: " + "; ".join(failures))
    sys.exit(1)
print("docs: no workshop words, links resolve, no measurement logs on user pages")
