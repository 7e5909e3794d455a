#!/usr/bin/python3
"""Checks that the docs hold together: every relative Markdown link in README.md, CHANGELOG.md and
docs/*.md names a file of the repository (and, with #anchor, a heading of it), and no tracked file
points at the shared folder beside the repository, which a clone does not have: whoever clones the
project must be able to follow every reference. Exits 0 when all is well, 1 with the faults listed.

usage: python3 tools/check_docs.py [REPO]   (default: the repository this script is in)
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def anchor(heading):
    """GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces to dashes."""
    text = re.sub(r"[`*_]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    found, fence = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fence = not fence
            elif not fence and line.startswith("#"):
                found.add(anchor(line.lstrip("#")))
    return found


def main():
    repo = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    faults = []
    docs = ["README.md", "CHANGELOG.md"] + sorted(
        os.path.join("docs", f) for f in os.listdir(os.path.join(repo, "docs")) if f.endswith(".md"))
    for doc in docs:
        path = os.path.join(repo, doc)
        if not os.path.exists(path):
            faults.append(f"{doc}: missing")
            continue
        with open(path, encoding="utf-8") as f:
            text = re.sub(r"```.*?```", "", f.read(), flags=re.S)  # links in code blocks are examples
        for target in LINK.findall(text):
            if re.match(r"[a-z]+:", target):  # https:, mailto:
                continue
            file, _, fragment = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file)) if file else path
            if not resolved.startswith(repo + os.sep) and resolved != repo:
                faults.append(f"{doc}: {target}: outside the repository")
            elif not os.path.exists(resolved):
                faults.append(f"{doc}: {target}: no such file")
            elif fragment and resolved.endswith(".md") and fragment not in anchors(resolved):
                faults.append(f"{doc}: {target}: no heading #{fragment} in {os.path.relpath(resolved, repo)}")
    beside = ".." + "/shared"  # written so that this file does not name it
    outside = subprocess.run(["git", "-C", repo, "grep", "-n", "-F", "-e", beside, "--", "."],
                             capture_output=True, text=True).stdout.strip()
    if outside:
        faults += [f"{line}: points outside the repository" for line in outside.splitlines()]
    for fault in faults:
        print(fault)
    print(f"{len(docs)} documents checked: " + ("ok" if not faults else f"{len(faults)} faults"))
    return 1 if faults else 0


if __name__ == "__main__":
    sys.exit(main())
