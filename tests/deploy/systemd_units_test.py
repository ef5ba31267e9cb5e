#!/usr/bin/env python3
"""tests/deploy/systemd_units_test.py BUILD_DIR WORKER

`cmake --install BUILD_DIR --component deploy` into a DESTDIR, for two prefixes, puts the systemd
units into <prefix>/lib/systemd/system with ExecStart naming <prefix>/bin/tessera-worker, and the
rest of deploy/ under <prefix>/share/tessera/deploy. The installed units:
  - carry the hardening the worker is meant to run under (docs/farm.md, "systemd"),
  - start the worker with its TLS certificate, key and token from LoadCredential= and its module
    cache in CacheDirectory=, with flags the real worker has (`tessera-worker --help`),
  - pass `systemd-analyze verify` without a warning, and `systemd-analyze security` rates their
    exposure at most 2.0 ("OK"; 1.2 when written), where systemd-analyze exists (it runs without
    a running systemd).
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outcome  # noqa: E402
import systemd_unit  # noqa: E402

UNITS = ("tessera-worker.service", "tessera-worker@.service")
SHARED = (
    "share/tessera/deploy/systemd/worker.env",
    "share/tessera/deploy/slurm/tessera-farm.sbatch",
    "share/tessera/deploy/slurm/tessera-frames.sbatch",
    "share/tessera/deploy/kubernetes/worker-statefulset.yaml",
    "share/tessera/deploy/kubernetes/make-secret.sh",
    "share/tessera/deploy/tls/make-certs.sh",
    "share/doc/Tessera/farm.md",
)
EXECUTABLE = (
    "share/tessera/deploy/slurm/tessera-farm.sbatch",
    "share/tessera/deploy/slurm/tessera-frames.sbatch",
    "share/tessera/deploy/kubernetes/make-secret.sh",
    "share/tessera/deploy/tls/make-certs.sh",
)
# Setting: the value it must have (single-valued settings; lists are checked below).
HARDENING = {
    "DynamicUser": "yes",
    "ProtectSystem": "strict",
    "ProtectHome": "yes",
    "PrivateTmp": "yes",
    "PrivateDevices": "yes",
    "NoNewPrivileges": "yes",
    "MemoryDenyWriteExecute": "yes",
    "RestrictNamespaces": "yes",
    "RestrictSUIDSGID": "yes",
    "LockPersonality": "yes",
    "ProtectKernelTunables": "yes",
    "ProtectKernelModules": "yes",
    "ProtectControlGroups": "yes",
    "UMask": "0077",
    "Restart": "on-failure",
    "Type": "exec",
}
CREDENTIALS = {"worker.pem": "/etc/tessera/worker.pem", "worker.key": "/etc/tessera/worker.key",
               "tessera.token": "/etc/tessera/tessera.token"}

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def worker_flags(worker):
    help_text = subprocess.run([worker, "--help"], capture_output=True, text=True,
                               check=True).stdout
    return set(re.findall(r"(--[a-z][a-z0-9-]*)", help_text))


def check_unit(path, prefix, flags):
    name = os.path.basename(path)
    with open(path) as f:
        text = f.read()
    check("@TESSERA_" not in text, f"{name}: a placeholder was left unconfigured")
    unit = systemd_unit.parse_unit(text)
    for key, expected in HARDENING.items():
        got = systemd_unit.value(unit, "Service", key)
        check(got == expected, f"{name}: {key}={got}, expected {expected}")
    check(unit["Service"].get("CapabilityBoundingSet") == [""],
          f"{name}: CapabilityBoundingSet must be assigned empty (no capabilities)")
    check(sorted(" ".join(systemd_unit.values(unit, "Service", "RestrictAddressFamilies")).split())
          == ["AF_INET", "AF_INET6", "AF_UNIX"],
          f"{name}: RestrictAddressFamilies must be AF_UNIX AF_INET AF_INET6")
    filters = systemd_unit.values(unit, "Service", "SystemCallFilter")
    check(filters and filters[0] == "@system-service",
          f"{name}: SystemCallFilter must allow @system-service first, got {filters}")
    check("-/etc/tessera/worker.env" in unit["Service"].get("EnvironmentFile", []),
          f"{name}: EnvironmentFile=-/etc/tessera/worker.env missing")
    loaded = dict(v.split(":", 1) for v in systemd_unit.values(unit, "Service", "LoadCredential"))
    check(loaded == CREDENTIALS, f"{name}: LoadCredential= {loaded}, expected {CREDENTIALS}")
    check(systemd_unit.value(unit, "Install", "WantedBy") == "multi-user.target",
          f"{name}: WantedBy=multi-user.target missing")

    cache = systemd_unit.value(unit, "Service", "CacheDirectory")
    argv = systemd_unit.exec_argv(systemd_unit.value(unit, "Service", "ExecStart"))
    check(argv[0] == f"{prefix}/bin/tessera-worker",
          f"{name}: ExecStart runs {argv[0]}, expected {prefix}/bin/tessera-worker")
    options = {}
    for i, word in enumerate(argv[1:], 1):
        if word.startswith("--"):
            check(word in flags, f"{name}: ExecStart passes {word}, which tessera-worker lacks")
            options[word] = argv[i + 1] if i + 1 < len(argv) else None
    check(options.get("--tls-cert") == "%d/worker.pem", f"{name}: --tls-cert not %d/worker.pem")
    check(options.get("--tls-key") == "%d/worker.key", f"{name}: --tls-key not %d/worker.key")
    check(options.get("--token-file") == "%d/tessera.token",
          f"{name}: --token-file not %d/tessera.token")
    check(cache is not None and options.get("--module-cache") == f"%C/{cache}",
          f"{name}: --module-cache {options.get('--module-cache')} is not the CacheDirectory "
          f"%C/{cache}")
    listen = options.get("--listen", "")
    if "@" in name:
        check(listen.endswith(":%i"), f"{name}: a template listens on its instance's port (%i)")
        check(cache.endswith("/%i"), f"{name}: each instance needs its own cache directory")
    else:
        check(listen == "${TESSERA_WORKER_LISTEN}",
              f"{name}: --listen should come from TESSERA_WORKER_LISTEN, got {listen}")
    check(argv[-1] == "$TESSERA_WORKER_ARGS",
          f"{name}: ExecStart should end with $TESSERA_WORKER_ARGS (worker.env's flags)")


def analyze(unit_dir, worker):
    """systemd-analyze verify and security on copies of the units whose ExecStart names the
    built worker (verify insists that the program exists)."""
    tool = shutil.which("systemd-analyze")
    if tool is None:
        print("systemd-analyze not found: verify and security not run (the checks above were)")
        return
    with tempfile.TemporaryDirectory() as tmp:
        for name in UNITS:
            with open(os.path.join(unit_dir, name)) as f:
                text = f.read()
            text = re.sub(r"^ExecStart=\S+", f"ExecStart={worker}", text, flags=re.M)
            with open(os.path.join(tmp, name), "w") as f:
                f.write(text)
        for name in ("tessera-worker.service", "tessera-worker@7000.service"):
            path = os.path.join(tmp, name)
            verify = subprocess.run([tool, "verify", "--man=no", path], capture_output=True,
                                    text=True)
            output = (verify.stdout + verify.stderr).strip()
            if check(verify.returncode == 0 and not output,
                     f"systemd-analyze verify {name}: status {verify.returncode}: {output}"):
                print(f"systemd-analyze verify {name}: no warnings")
            security = subprocess.run(
                [tool, "security", "--offline=yes", "--threshold=20", "--no-pager", path],
                capture_output=True, text=True)
            level = re.search(r"Overall exposure level for \S+: ([0-9.]+)", security.stdout)
            check(security.returncode == 0,
                  f"systemd-analyze security {name}: exposure "
                  f"{level.group(1) if level else '?'} over 2.0:\n{security.stdout}")
            if level:
                print(f"systemd-analyze security {name}: exposure {level.group(1)}")


def main():
    build_dir, worker = sys.argv[1], os.path.abspath(sys.argv[2])
    flags = worker_flags(worker)
    with tempfile.TemporaryDirectory() as tmp:
        for prefix in ("/usr", "/opt/tessera"):
            destdir = os.path.join(tmp, prefix.strip("/").replace("/", "_"))
            install = subprocess.run(
                ["cmake", "--install", build_dir, "--component", "deploy", "--prefix", prefix],
                env=dict(os.environ, DESTDIR=destdir), capture_output=True, text=True)
            if not check(install.returncode == 0,
                         f"cmake --install --component deploy --prefix {prefix}: "
                         f"{install.stdout}{install.stderr}"):
                continue
            root = destdir + prefix
            unit_dir = os.path.join(root, "lib/systemd/system")
            for name in UNITS:
                path = os.path.join(unit_dir, name)
                if check(os.path.isfile(path), f"--prefix {prefix}: no lib/systemd/system/{name}"):
                    check_unit(path, prefix, flags)
            for rel in SHARED:
                check(os.path.isfile(os.path.join(root, rel)), f"--prefix {prefix}: no {rel}")
            for rel in EXECUTABLE:
                path = os.path.join(root, rel)
                check(not os.path.exists(path) or os.access(path, os.X_OK),
                      f"--prefix {prefix}: {rel} is not executable")
            if prefix == "/usr":
                analyze(unit_dir, worker)
    return outcome.report(failures)


if __name__ == "__main__":
    sys.exit(main())
