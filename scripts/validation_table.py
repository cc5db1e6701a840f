#!/usr/bin/python3
"""Writes the table of published figures in docs/validation.md from a ctest run's own output.

Every test that guards a figure prints it as `[figure] NAME: measured M, bound B` (or `bound >= B` for a figure that
must stay at or above B; tests/figures.hpp). Figures whose name ends in "(negative control)" are a broken method's,
printed by the control that shows the check fails it: they are left out. This script
reads those lines from a CTest log, with the test that printed each, and replaces the table between the markers
`<!-- figures: begin -->` and `<!-- figures: end -->` of docs/validation.md. Nothing else in the file changes.

    ctest --test-dir build -j2 && scripts/validation_table.py build/Testing/Temporary/LastTest.log

A figure missing from the log (its test did not run) is an error: the table would otherwise drop it silently.
Use --check to compare without writing (exit 1 when the file differs from what the log gives).
"""
import argparse
import pathlib
import re
import sys

BEGIN, END = "<!-- figures: begin -->", "<!-- figures: end -->"
TEST = re.compile(r"^\d+/\d+ Testing: (\S+)")
FIGURE = re.compile(r"^\[figure\] (.+): measured (\S+), bound (>= )?(\S+)$")


def read_figures(log: pathlib.Path):
    figures, test = {}, None
    for line in log.read_text(errors="replace").splitlines():
        m = TEST.match(line)
        if m:
            test = m.group(1).split("<")[0]
            continue
        m = FIGURE.match(line)
        if m and test and not m.group(1).endswith("(negative control)"):
            figures[m.group(1)] = (test, float(m.group(2)), float(m.group(4)), bool(m.group(3)))
    return figures


def table(figures) -> str:
    rows = ["| figure | test | bound | measured | margin |", "|---|---|---:|---:|---:|"]
    for name, (test, measured, bound, at_least) in sorted(figures.items(), key=lambda kv: (kv[1][0], kv[0])):
        if at_least:
            ratio = f"{measured / bound:.1f}"
        else:
            ratio = "—" if measured == 0 else f"{bound / measured:.1f}"
        shown = f"≥ {bound:.3g}" if at_least else f"{bound:.3g}"
        rows.append(f"| {name.replace('|', chr(92) + '|')} | `{test}` | {shown} | {measured:.3g} | {ratio} |")
    return "\n".join(rows)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log", type=pathlib.Path, help="a CTest log (build/Testing/Temporary/LastTest.log)")
    parser.add_argument("--doc", type=pathlib.Path,
                        default=pathlib.Path(__file__).resolve().parent.parent / "docs" / "validation.md")
    parser.add_argument("--check", action="store_true", help="compare only; exit 1 if the document differs")
    args = parser.parse_args()
    figures = read_figures(args.log)
    if not figures:
        print(f"validation_table.py: {args.log}: no [figure] lines (run the whole ctest first)", file=sys.stderr)
        return 1
    text = args.doc.read_text()
    if text.count(BEGIN) != 1 or text.count(END) != 1:
        print(f"validation_table.py: {args.doc}: needs one {BEGIN} and one {END}", file=sys.stderr)
        return 1
    head, rest = text.split(BEGIN)
    old, tail = rest.split(END)
    known = {name.replace("\\|", "|") for name in re.findall(r"^\| (.+?) \| `", old, re.M)}
    missing = sorted(known - figures.keys())
    if missing:
        print(f"validation_table.py: {args.log}: {len(missing)} figure(s) of the table not in the log, e.g. "
              f"'{missing[0]}' (a partial ctest run?)", file=sys.stderr)
        return 1
    new = f"{head}{BEGIN}\n{table(figures)}\n{END}{tail}"
    if args.check:
        if new != text:
            print(f"validation_table.py: {args.doc} differs from {args.log}'s figures", file=sys.stderr)
            return 1
        return 0
    args.doc.write_text(new)
    print(f"validation_table.py: {len(figures)} figures written to {args.doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
