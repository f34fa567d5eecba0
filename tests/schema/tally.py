"""A pass/fail tally for the schema checks: expect() each point, then finish() prints the
closing line 'NAME: N passed, M failed' and exits 1 on any failure."""
import sys

counts = {"passed": 0, "failed": 0}


def expect(ok, what):
    if ok:
        counts["passed"] += 1
    else:
        counts["failed"] += 1
        print("FAIL:", what)


def finish(name):
    print(f"{name}: {counts['passed']} passed, {counts['failed']} failed")
    sys.exit(1 if counts["failed"] else 0)
