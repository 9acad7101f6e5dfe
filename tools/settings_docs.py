#!/usr/bin/env python3
"""settings_docs: write (or check) the tables of the docs made from the code's lists.

Usage: tools/settings_docs.py OCG_SLAM [--docs docs/settings.md --docs docs/ocg.md] [--check]

Every options struct lists its keys once (include/ocg/core/option_fields.h), the OCG's
judgement terms are listed once (src/ocg/judgement_terms.cc) and so are the fields of its
keyframe observation (include/ocg/ocg/observation.h); `ocg_slam settings --markdown` prints
them as tables, each between the lines `<!-- settings-table NAME -->` and
`<!-- end settings-table -->`. This replaces each such block of the docs (a block lives in
one of the --docs files) with the one printed; the prose around them is left alone. --check
changes nothing and exits 1 when a block is out of date or missing (the tests
Settings.DocsTablesAreTheFieldLists and JudgementTerms.DocsTablesAreTheRegistries check the
same).
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
    parser.add_argument("--docs", action="append",
                        help="a docs file holding blocks (repeatable; default docs/settings.md "
                             "and docs/ocg.md)")
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    docs_files = args.docs or ["docs/settings.md", "docs/ocg.md"]
    printed = subprocess.run([args.ocg_slam, "settings", "--markdown"], check=True,
                             capture_output=True, text=True).stdout
    tables = {m.group(1): m.group(0) for m in BLOCK.finditer(printed)}
    found = set()
    outdated = []
    for path in docs_files:
        with open(path, encoding="utf-8") as f:
            docs = f.read()

        def replace(match):
            found.add(match.group(1))
            if match.group(1) not in tables:
                sys.exit("%s: settings-table %s is no section of ocg_slam settings --markdown"
                         % (path, match.group(1)))
            return tables[match.group(1)]

        updated = BLOCK.sub(replace, docs)
        if updated == docs:
            continue
        outdated.append(path)
        if not args.check:
            with open(path + ".tmp", "w", encoding="utf-8") as f:
                f.write(updated)
            os.replace(path + ".tmp", path)
            print("%s: tables written" % path)
    missing = sorted(set(tables) - found)
    if missing:
        sys.exit("%s: no settings-table block for %s: add '<!-- settings-table NAME -->' and "
                 "'<!-- end settings-table -->' lines where each belongs"
                 % (", ".join(docs_files), ", ".join(missing)))
    if args.check:
        if outdated:
            print("%s: tables out of date; run tools/settings_docs.py %s"
                  % (", ".join(outdated), args.ocg_slam))
            return 1
        print("%s: the tables are up to date" % ", ".join(docs_files))
        return 0
    if not outdated:
        print("%s: already up to date" % ", ".join(docs_files))
    return 0


if __name__ == "__main__":
    sys.exit(main())
