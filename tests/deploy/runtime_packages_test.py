#!/usr/bin/env python3
"""tests/deploy/runtime_packages_test.py SOURCE_DIR BINARY...

Every shared library the built programs link (their DT_NEEDED entries, as the loader finds them
here) comes from a package of `deploy/install-deps.sh --print-runtime` (or libc6, libgcc-s1,
which every Debian has), or from Tessera itself. That list is what the container image's final
stage installs, so a program that starts linking a new library fails this test instead of the
image at run time. Skips (77) on a machine without dpkg.
"""

import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outcome  # noqa: E402

ALWAYS_THERE = {"libc6", "libgcc-s1"}


def spellings(path):
    """The path, resolved, in both spellings of merged /usr (dpkg knows one of them)."""
    out = {path, os.path.realpath(path)}
    for p in list(out):
        if p.startswith("/usr/lib/"):
            out.add(p[len("/usr"):])
        elif p.startswith("/lib/"):
            out.add("/usr" + p)
    return out


def packages_of(paths):
    """{path: package} for the paths dpkg knows, in one dpkg-query (each call reads its whole
    database)."""
    result = subprocess.run(["dpkg-query", "-S", *sorted(paths)], capture_output=True, text=True)
    owners = {}
    for line in result.stdout.splitlines():
        package, _, path = line.partition(": ")
        for p in path.split(", "):
            owners[p.strip()] = package.split(":")[0].split(",")[0].strip()
    return owners


def main():
    source_dir, binaries = sys.argv[1], sys.argv[2:]
    if shutil.which("dpkg-query") is None:
        print("SKIP: no dpkg-query: the runtime list names Debian packages")
        return 77
    runtime = set(subprocess.run([os.path.join(source_dir, "deploy/install-deps.sh"),
                                  "--print-runtime"], capture_output=True, text=True,
                                 check=True).stdout.split())
    failures = []
    libraries = {}  # binary: {library: path}
    for binary in binaries:
        if not os.path.exists(binary):
            failures.append(f"{binary} was not built")
            continue
        dynamic = subprocess.run(["readelf", "-d", binary], capture_output=True, text=True,
                                 check=True).stdout
        needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", dynamic)
        resolved = dict(re.findall(r"^\s*(\S+) => (/\S+)", subprocess.run(
            ["ldd", binary], capture_output=True, text=True, check=True).stdout, flags=re.M))
        # Tessera's own libraries are installed with it; the loader is libc6's.
        libraries[binary] = {lib: resolved.get(lib) for lib in needed
                             if not lib.startswith(("libtessera", "ld-linux"))}
    owners = packages_of({s for libs in libraries.values() for path in libs.values() if path
                          for s in spellings(path)})
    for binary, libs in libraries.items():
        packages = set()
        for library, path in sorted(libs.items()):
            package = next((owners[s] for s in sorted(spellings(path)) if s in owners),
                           None) if path else None
            if package is None:
                failures.append(f"{os.path.basename(binary)}: {library} ({path}) is in no package")
                continue
            packages.add(package)
            if package not in runtime | ALWAYS_THERE:
                failures.append(f"{os.path.basename(binary)} links {library} from {package}, "
                                "which deploy/install-deps.sh --runtime does not install")
        print(f"{os.path.basename(binary)}: {', '.join(sorted(packages))}")
    return outcome.report(failures)


if __name__ == "__main__":
    sys.exit(main())
