#!/usr/bin/env python3
"""settings_docs: write (or check) the settings tables of docs/settings.md.

Usage: tools/settings_docs.py OCG_SLAM [--docs docs/settings.md] [--check]

Every options struct lists its keys once (include/ocg/core/option_fields.h); `ocg_slam
settings --markdown` prints them as tables, each between the lines
`<!-- settings-table NAME -->` and `<!-- end settings-table -->`. This replaces each such
block of the docs with the one printed (the prose around them is left alone). --check
changes nothing and exits 1 when a block is out of date or missing (the test
Settings.DocsTablesAreTheFieldLists checks the same).
"""
import argparse
import os
import re
import subprocess
import sys

BLOCK = re.compile(r"<!-- settings-table (\S+) -->\n.*?<!-- end settings-table -->\n", re.S)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("ocg_slam", help="the ocg_slam executable of a build")
    parser.add_argument("--docs", default="docs/settings.md")
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    printed = subprocess.run([args.ocg_slam, "settings", "--markdown"], check=True,
                             capture_output=True, text=True).stdout
    tables = {m.group(1): m.group(0) for m in BLOCK.finditer(printed)}
    with open(args.docs, encoding="utf-8") as f:
        docs = f.read()
    found = set()

    def replace(match):
        found.add(match.group(1))
        if match.group(1) not in tables:
            sys.exit("%s: settings-table %s is no section of ocg_slam settings --markdown"
                     % (args.docs, match.group(1)))
        return tables[match.group(1)]

    updated = BLOCK.sub(replace, docs)
    missing = sorted(set(tables) - found)
    if missing:
        sys.exit("%s: no settings-table block for %s: add '<!-- settings-table NAME -->' and "
                 "'<!-- end settings-table -->' lines where each belongs" % (args.docs,
                                                                             ", ".join(missing)))
    if args.check:
        if updated != docs:
            print("%s: the settings tables are out of date; run tools/settings_docs.py %s"
                  % (args.docs, args.ocg_slam))
            return 1
        print("%s: the settings tables are up to date" % args.docs)
        return 0
    if updated != docs:
        with open(args.docs + ".tmp", "w", encoding="utf-8") as f:
            f.write(updated)
        os.replace(args.docs + ".tmp", args.docs)
        print("%s: tables written" % args.docs)
    else:
        print("%s: already up to date" % args.docs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
