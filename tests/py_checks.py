"""The plain-Python tests' reporting: one line per check, and an exit
status that is non-zero when any check failed."""
import sys

failed = []


def check(name, ok, detail):
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {detail}")
    if not ok:
        failed.append(name)


def finish():
    if failed:
        sys.exit(f"{len(failed)} check(s) failed: {', '.join(failed)}")
    print("all checks passed")
    sys.exit(0)
