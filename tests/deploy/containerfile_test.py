#!/usr/bin/env python3
"""tests/deploy/containerfile_test.py SOURCE_DIR [WORKER]

deploy/container/Containerfile cannot be built here (no container engine, no registry), and
hadolint is not a Debian package, so this reads it the way a builder would and checks:
  - two stages, both FROM debian:bookworm-slim (ARG defaults resolved), the final one copying
    only the installed prefix from the build stage;
  - packages come from deploy/install-deps.sh alone (--build in the build stage, --runtime in the
    final one; the lists themselves are checked by runtime_packages_test.py), no apt-get of its
    own;
  - every COPY source exists in the repository and is not left out by the ignore file;
  - the final stage runs as a fixed non-root uid, the one deploy/kubernetes runs its pods as;
  - it EXPOSEs the ports the worker StatefulSet declares, and its ENTRYPOINT is the installed
    tessera-worker, given flags the worker has (with WORKER: `tessera-worker --help`; flags other
    engineers are adding, such as --status-listen, are named when the worker lacks them).
"""

import fnmatch
import json
import os
import re
import subprocess
import sys

import yaml

PENDING_FLAGS = {"--status-listen", "--log-level", "--version"}  # issue 27, landing separately


def instructions(text):
    """(INSTRUCTION, arguments) pairs, continuation lines joined, comments dropped."""
    out, pending = [], ""
    for line in text.splitlines():
        stripped = line.strip()
        if not pending and (not stripped or stripped.startswith("#")):
            continue
        if pending and stripped.startswith("#"):
            continue
        if stripped.endswith("\\"):
            pending += stripped[:-1] + " "
            continue
        full = pending + stripped
        pending = ""
        word, _, rest = full.partition(" ")
        out.append((word.upper(), rest.strip()))
    return out


def main():
    source_dir = sys.argv[1]
    worker = sys.argv[2] if len(sys.argv) > 2 else None
    with open(os.path.join(source_dir, "deploy/container/Containerfile")) as f:
        parsed = instructions(f.read())
    with open(os.path.join(source_dir, "deploy/container/Containerfile.dockerignore")) as f:
        ignored = [l.strip() for l in f if l.strip() and not l.startswith("#")]
    failures = []

    def check(condition, message):
        if not condition:
            failures.append(message)

    args, stages = {}, []
    for word, rest in parsed:
        if word == "ARG" and not stages:
            name, _, default = rest.partition("=")
            args[name] = default
        elif word == "FROM":
            image = re.sub(r"\$\{(\w+)\}", lambda m: args.get(m.group(1), ""), rest.split()[0])
            name = rest.split()[2] if " AS " in rest.upper() else None
            stages.append({"image": image, "name": name, "body": []})
        else:
            check(bool(stages), f"{word} before the first FROM")
            if stages:
                stages[-1]["body"].append((word, rest))
    check(len(stages) == 2, f"{len(stages)} stages, expected a build stage and a final one")
    if len(stages) != 2:
        print("FAIL:\n  " + "\n  ".join(failures))
        return 1
    build, final = stages
    for stage in stages:
        check(stage["image"] == "debian:bookworm-slim",
              f"a stage starts FROM {stage['image']}, expected debian:bookworm-slim")
    check(build["name"] is not None, "the build stage has no name for COPY --from")

    def runs(stage):
        return " ; ".join(rest for word, rest in stage["body"] if word == "RUN")

    check(re.search(r"install-deps\.sh --build\b", runs(build)) is not None,
          "the build stage does not install with deploy/install-deps.sh --build")
    check("cmake --install" in runs(build), "the build stage does not cmake --install")
    check(re.search(r"install-deps\.sh --runtime\b", runs(final)) is not None,
          "the final stage does not install with deploy/install-deps.sh --runtime")
    for stage in stages:
        check("apt-get" not in runs(stage),
              "a stage runs apt-get itself: packages come from deploy/install-deps.sh's lists")
        check("/var/lib/apt/lists" in runs(stage), "a stage keeps apt's lists in its layer")

    for stage in stages:
        for word, rest in stage["body"]:
            if word != "COPY" or "--from=" in rest:
                continue
            source = rest.split()[0]
            if source == ".":
                continue
            check(os.path.exists(os.path.join(source_dir, source)),
                  f"COPY {source}: not in the repository")
            check(not any(fnmatch.fnmatch(source, p) or source.startswith(p.rstrip("*") + "/")
                          for p in ignored), f"COPY {source}: the ignore file leaves it out")
    copies = [rest for word, rest in final["body"] if word == "COPY" and "--from=" in rest]
    check(copies == [f"--from={build['name']} /opt/tessera /opt/tessera"],
          f"the final stage should copy /opt/tessera alone from the build stage, copies {copies}")

    users = [rest for word, rest in final["body"] if word == "USER"]
    user = users[-1].split(":")[0] if users else "root"
    check(user.isdigit() and int(user) != 0,
          f"USER {user}: must be a numeric uid other than 0 (Kubernetes checks runAsNonRoot "
          "against a number)")
    k8s_dir = os.path.join(source_dir, "deploy/kubernetes")
    pod_users, container_ports = set(), set()
    for name in sorted(os.listdir(k8s_dir)):
        if not name.endswith(".yaml"):
            continue
        with open(os.path.join(k8s_dir, name)) as f:
            for doc in yaml.safe_load_all(f):
                spec = ((doc or {}).get("spec") or {}).get("template", {}).get("spec")
                if not spec:
                    continue
                pod_users.add(str(spec.get("securityContext", {}).get("runAsUser")))
                if doc["kind"] == "StatefulSet":
                    for container in spec["containers"]:
                        container_ports |= {str(p["containerPort"]) for p in container["ports"]}
    check(pod_users == {user}, f"USER {user}, but Kubernetes pods run as {sorted(pod_users)}")
    exposed = set(" ".join(rest for word, rest in final["body"] if word == "EXPOSE").split())
    check(exposed == container_ports,
          f"EXPOSE {sorted(exposed)}, the worker StatefulSet's ports {sorted(container_ports)}")

    entrypoint = [json.loads(rest) for word, rest in final["body"] if word == "ENTRYPOINT"]
    check(entrypoint == [["/opt/tessera/bin/tessera-worker"]],
          f"ENTRYPOINT {entrypoint}: expected the exec form of /opt/tessera/bin/tessera-worker")
    cmd = [json.loads(rest) for word, rest in final["body"] if word == "CMD"]
    check(len(cmd) == 1, "no CMD (the worker's default flags)")
    if cmd and worker:
        help_text = subprocess.run([worker, "--help"], capture_output=True, text=True).stdout
        known = set(re.findall(r"(--[a-z][a-z0-9-]*)", help_text))
        for flag in (a for a in cmd[0] if a.startswith("--")):
            if flag in known:
                continue
            if flag in PENDING_FLAGS:
                print(f"SKIP (one assertion): this tessera-worker has no {flag} yet")
            else:
                failures.append(f"CMD passes {flag}, which tessera-worker lacks")

    if failures:
        print("FAIL:\n  " + "\n  ".join(failures))
        return 1
    print(f"PASS: stages {build['image']} AS {build['name']} -> {final['image']}, USER {user}, "
          f"EXPOSE {' '.join(sorted(exposed))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
