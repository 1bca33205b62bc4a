#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Check the reStructuredText pages of Documentation/ (and any .rst given).

  scripts/check-docs.py [--root DIR] [FILE.rst ...]

Each page is parsed by docutils with warnings as errors (a malformed table,
a short title underline, a list that ends without a blank line, a broken
internal link: what a reader's renderer would show wrong or drop). Without
FILE arguments, every file git tracks under the root (pages, sources,
comments, README.md) is also read for a pointer out of the project (a path
into the project workspace's shared/ folder: a user's clone has none; cite
the manual by title instead). Prints one line per problem, naming the file
and line, then a summary; exits 1 if there was a problem, 2 when docutils
is missing.
"""

import argparse
import io
import pathlib
import re
import subprocess
import sys

try:
    import docutils.core
    import docutils.utils
except ImportError:
    print("check-docs: docutils is missing (Debian: apt-get install python3-docutils; "
          "scripts/install-deps.sh installs it)", file=sys.stderr)
    sys.exit(2)

# A path into the workspace outside the project: ../shared/..., shared/spec,
# shared/seeds, shared/design.
OUTSIDE = re.compile(r"(\.\./shared/|\bshared/(spec|seeds|design)\b)")


def outside(path: pathlib.Path, text: str) -> list[str]:
    problems = []
    for n, line in enumerate(text.splitlines(), 1):
        m = OUTSIDE.search(line)
        if m:
            problems.append(f"{path}:{n}: points outside the project ({m.group(0)}): "
                            "cite the manual by title and version")
    return problems


def tracked(root: pathlib.Path) -> list[pathlib.Path]:
    """The files git tracks under root, but this check and its tests (which
    name the paths they look for)."""
    out = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], capture_output=True, check=True).stdout
    skip = {"scripts/check-docs.py", "tests/docs/test-check-docs.sh"}
    return [root / f for f in out.decode().split("\0") if f and f not in skip]


def check(path: pathlib.Path) -> list[str]:
    text = path.read_text(encoding="utf-8")
    problems = outside(path, text)
    errors = io.StringIO()
    try:
        docutils.core.publish_doctree(
            text, source_path=str(path),
            settings_overrides={"report_level": 2, "halt_level": 2, "warning_stream": errors,
                                "file_insertion_enabled": False, "raw_enabled": False})
    except docutils.utils.SystemMessage as e:
        problems.append(str(e).strip())
    return problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=pathlib.Path(__file__).resolve().parent.parent, type=pathlib.Path)
    ap.add_argument("files", nargs="*", type=pathlib.Path)
    a = ap.parse_args()
    files = a.files or sorted((a.root / "Documentation").glob("*.rst"))
    if not files:
        print(f"check-docs: no .rst files under {a.root / 'Documentation'}", file=sys.stderr)
        return 1
    problems = []
    for f in files:
        problems += check(f)
    scanned = 0
    if not a.files:
        pages = set(files)
        for f in tracked(a.root):
            if f in pages or not f.is_file() or f.is_symlink():
                continue
            try:
                text = f.read_text(encoding="utf-8")
            except (UnicodeDecodeError, OSError):
                continue  # not text
            problems += outside(f.relative_to(a.root), text)
            scanned += 1
    for p in problems:
        print(p)
    tree = f" and {scanned} other files" if scanned else ""
    print(f"check-docs: {len(files)} pages{tree}, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
