"""How every tests/deploy check ends: its failures listed under FAIL, or PASS; the exit status."""


def report(failures):
    if failures:
        print("FAIL:\n  " + "\n  ".join(failures))
        return 1
    print("PASS")
    return 0
