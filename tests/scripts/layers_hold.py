#!/usr/bin/env python3
"""A layer includes only the ones below it (docs/architecture.md, "Layers"): every
`#include "crowd/<layer>/..."` in a folder's sources names a layer that folder may use, and none
reaches into another folder by relative path (`#include "../..."`: what a folder offers others
is in its public headers). The samples link no bake code; no library includes an application.

usage: layers_hold.py SOURCE_DIR"""
import pathlib
import re
import sys

# Folder: the layers its sources may include.
ALLOWED = {
    "formats": {"formats"},
    "support": {"formats", "support"},
    "runtime": {"formats", "support", "runtime"},
    "bake": {"formats", "support", "runtime", "bake"},
    "samples": {"formats", "support", "samples"},
    "apps/crowdplay": {"formats", "support", "runtime"},
    "apps/crowdbake": {"formats", "support", "runtime", "bake", "samples"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]crowd/([a-z_]+)/', re.M)
RELATIVE = re.compile(r'^\s*#\s*include\s*"(\.\./[^"]*)"', re.M)


def main():
    source = pathlib.Path(sys.argv[1])
    problems, files = [], 0
    for folder, allowed in ALLOWED.items():
        for path in sorted((source / folder).rglob("*")):
            if path.suffix not in (".cpp", ".h"):
                continue
            files += 1
            text = path.read_text()
            for header in RELATIVE.findall(text):
                problems.append(f"{path.relative_to(source)} includes {header} by relative "
                                f"path (include another folder's public header)")
            for layer in INCLUDE.findall(text):
                if layer not in allowed:
                    problems.append(f"{path.relative_to(source)} includes crowd/{layer}/, "
                                    f"which {folder}/ may not use")
    if files == 0:
        problems.append(f"no sources found under {source}")
    for p in problems:
        print(p)
    print(f"{files} files in {len(ALLOWED)} folders: "
          + ("layers hold" if not problems else f"{len(problems)} includes across layers"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
