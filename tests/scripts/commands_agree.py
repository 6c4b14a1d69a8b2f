#!/usr/bin/env python3
"""The command list is in one place (kCommands in apps/crowdbake/crowdbake.cpp): `crowdbake
--help` lists it, and README.md's table and docs/commands.md must name the same commands, each
of which answers its own --help.

usage: commands_agree.py BIN_DIR SOURCE_DIR"""
import re
import subprocess
import sys


def main():
    bin_dir, source = sys.argv[1], sys.argv[2]
    crowdbake = bin_dir + "/crowdbake"
    help_text = subprocess.run([crowdbake, "--help"], check=True, capture_output=True,
                               text=True).stdout
    listed = help_text.split("\ncommands:\n", 1)[1].split("\n\n", 1)[0]
    in_help = re.findall(r"^  ([a-z][a-z-]*) ", listed, re.M)
    with open(source + "/README.md") as f:
        rows = [line for line in f if line.startswith("| `")]
    in_readme = [name for row in rows for name in re.findall(r"`([a-z][a-z-]*)`",
                                                             row.split("|")[1])]
    with open(source + "/docs/commands.md") as f:
        in_docs = re.findall(r"^ {4,}crowdbake ([a-z][a-z-]*)\b", f.read(), re.M)
    problems = []
    for where, names in (("README.md's table", in_readme), ("docs/commands.md", in_docs)):
        for name in sorted(set(in_help) - set(names)):
            problems.append(f"{where} leaves out '{name}', which crowdbake --help lists")
        for name in sorted(set(names) - set(in_help)):
            problems.append(f"{where} names '{name}', which crowdbake --help does not list")
    if len(in_help) < 10:
        problems.append(f"crowdbake --help lists {len(in_help)} commands: {in_help}")
    for name in in_help:
        run = subprocess.run([crowdbake, name, "--help"], capture_output=True, text=True)
        if run.returncode != 0 or not run.stdout.strip():
            problems.append(f"'crowdbake {name} --help' exits {run.returncode}: "
                            f"{run.stderr.strip()[:200]}")
    for p in problems:
        print("commands_agree: " + p)
    print(f"commands_agree: {len(in_help)} commands in --help, {len(set(in_readme))} in "
          f"README.md, {len(set(in_docs))} in docs/commands.md")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
