#!/usr/bin/env python3
"""What the failed tests of the last ctest run said: the last lines of each
one's output, from ctest's own record (Testing/Temporary/LastTest.log and
LastTestsFailed.log). tools/test gathers it after each failing pass and
prints it, for every failing pass, just before its last line, so that a
log read from its end (CI keeps the end of a long log) shows why a test
failed, not only that it did.

usage: failed_output.py TESTING_TEMPORARY_DIR [LINES]
"""
import os
import re
import sys


def failed_names(tmp):
    try:
        with open(os.path.join(tmp, "LastTestsFailed.log")) as f:
            return [line.strip().split(":", 1)[1] for line in f if ":" in line]
    except FileNotFoundError:
        return []


def outputs(tmp):
    """{test name: its output lines} from LastTest.log."""
    found, name, lines, inside = {}, None, [], False
    try:
        f = open(os.path.join(tmp, "LastTest.log"), errors="replace")
    except FileNotFoundError:
        return found
    with f:
        for line in f:
            m = re.match(r"\d+/\d+ Test: (\S+)", line)
            if m:
                name, lines, inside = m.group(1), [], False
            elif name and line.startswith("Output:"):
                inside = True
            elif inside and line.startswith("<end of output>"):
                found[name], inside = lines, False
            elif inside and not line.startswith("-" * 58):
                lines.append(line.rstrip("\n"))
    return found


def main(tmp, keep=30):
    said = outputs(tmp)
    for name in failed_names(tmp):
        lines = said.get(name)
        if lines is None:
            print(f"--- {name}: no output of it in ctest's record")
            continue
        cut = len(lines) > keep
        print(f"--- {name}: the last {keep if cut else len(lines)} of its {len(lines)} output lines")
        for line in lines[-keep:]:
            print(f"    {line[:600]}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 30)
