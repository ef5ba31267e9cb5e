#!/usr/bin/env python3
"""tests/deploy/worker_sandbox_test.py SOURCE_DIR WORKER TUTORIAL

Runs tessera-worker the way deploy/systemd/tessera-worker.service runs it, without systemd (no
systemd runs here as PID 1), and renders through it:
  - the command line is the unit's ExecStart, with its specifiers and variables expanded (the
    credentials made by deploy/tls/make-certs.sh, as LoadCredential= hands them over);
  - the sandbox is the unit's, rebuilt from its settings: a private mount namespace with every
    file system read-only (ProtectSystem=strict) but the CacheDirectory=, an empty /tmp
    (PrivateTmp=), /home and /root hidden (ProtectHome=), an unprivileged user with no
    capabilities (DynamicUser=, CapabilityBoundingSet=), NoNewPrivileges=, UMask=, and the
    seccomp filters systemd installs for SystemCallFilter= (the groups as this machine's
    systemd-analyze lists them), MemoryDenyWriteExecute= and RestrictAddressFamilies=.
The tutorial's image through that worker, over TLS with the token, must equal the image on an
inproc device; program modules must land in the cache directory (dlopen works under
MemoryDenyWriteExecute); /healthz must answer on --status-listen (skipped while the worker lacks
the flag); SIGTERM must stop the worker with status 0. The sandbox proves itself first: a
writable and executable mapping, a netlink socket and a system call outside the filter must be
refused, and / and /usr must be read-only.
Needs root (namespaces, a user switch); skips (77) otherwise.
"""

import ctypes
import ctypes.util
import errno
import json
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outcome  # noqa: E402
import systemd_unit  # noqa: E402

# The render command, one place to switch it: tessera-tutorial (the test's third argument) until
# `tessera render` exists; then [renderer, "render", SCENE, "-o", out, "--spp", "4"].
def render_command(renderer, out):
    return [renderer, "--step", "10", "--width", "96", "--height", "64", "--out", out]


SERVICE_UID = 61234  # in systemd's DynamicUser= range (61184-65519)
CLONE_NEWNS = 0x00020000
MS_RDONLY, MS_NOSUID, MS_NODEV, MS_NOEXEC = 1, 2, 4, 8
MS_REMOUNT, MS_BIND, MS_REC, MS_PRIVATE = 32, 4096, 16384, 1 << 18
MOUNT_FLAGS = {"nosuid": MS_NOSUID, "nodev": MS_NODEV, "noexec": MS_NOEXEC, "noatime": 1024,
               "nodiratime": 2048, "relatime": 1 << 21, "nosymfollow": 256}
PR_CAPBSET_DROP, PR_SET_NO_NEW_PRIVS = 24, 38
PROT_READ, PROT_WRITE, PROT_EXEC = 1, 2, 4
MAP_PRIVATE, MAP_ANONYMOUS = 2, 0x20
SHM_EXEC = 0o100000
SCMP_ACT_ALLOW = 0x7FFF0000
SCMP_CMP_EQ, SCMP_CMP_GE, SCMP_CMP_MASKED_EQ = 4, 5, 7
AF_MAX = 46


def scmp_act_errno(number):
    return 0x00050000 | (number & 0xFFFF)


class ScmpArgCmp(ctypes.Structure):
    _fields_ = [("arg", ctypes.c_uint), ("op", ctypes.c_int), ("datum_a", ctypes.c_uint64),
                ("datum_b", ctypes.c_uint64)]


# ---------------------------------------------------------------- inside the sandbox (child) --

def libc():
    lib = ctypes.CDLL(None, use_errno=True)
    lib.mount.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_ulong,
                          ctypes.c_void_p]
    lib.mmap.restype = ctypes.c_void_p
    lib.mmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int, ctypes.c_int,
                         ctypes.c_int, ctypes.c_long]
    lib.prctl.argtypes = [ctypes.c_int, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong,
                          ctypes.c_ulong]
    return lib


def mount(lib, source, target, fstype, flags, data=None):
    if lib.mount(source and source.encode(), target.encode(), fstype and fstype.encode(), flags,
                 data and ctypes.c_char_p(data.encode())) != 0:
        e = ctypes.get_errno()
        raise OSError(e, f"mount {target}: {os.strerror(e)}")


def mounts():
    """(mount point, per-mount flags) of this namespace, parents before children."""
    out = []
    with open("/proc/self/mountinfo") as f:
        for line in f:
            fields = line.split()
            point = fields[4].encode().decode("unicode_escape")
            flags = 0
            for option in fields[5].split(","):
                flags |= MOUNT_FLAGS.get(option, 0)
            out.append((point, flags))
    return sorted(out, key=lambda m: m[0].count("/") if m[0] != "/" else 0)


def under(path, roots):
    return any(path == r or path.startswith(r.rstrip("/") + "/") for r in roots)


def make_filter(seccomp, default_action):
    ctx = seccomp.seccomp_init(default_action)
    if not ctx:
        raise OSError("seccomp_init failed")
    return ctx


def add_rule(seccomp, ctx, action, name, *comparisons):
    nr = seccomp.seccomp_syscall_resolve_name(name.encode())
    if nr < 0:
        return  # not a system call of this architecture
    args = (ScmpArgCmp * max(1, len(comparisons)))(*comparisons)
    rc = seccomp.seccomp_rule_add_array(ctx, action, nr, len(comparisons), args)
    if rc != 0:
        raise OSError(-rc, f"seccomp rule for {name}: {os.strerror(-rc)}")


def load(seccomp, ctx):
    rc = seccomp.seccomp_load(ctx)
    seccomp.seccomp_release(ctx)
    if rc != 0:
        raise OSError(-rc, f"seccomp_load: {os.strerror(-rc)}")


def launch(spec):
    """Builds the unit's sandbox around this process, proves it, then becomes the worker."""
    lib = libc()
    seccomp = ctypes.CDLL(ctypes.util.find_library("seccomp") or "libseccomp.so.2")
    seccomp.seccomp_init.restype = ctypes.c_void_p
    seccomp.seccomp_init.argtypes = [ctypes.c_uint32]
    seccomp.seccomp_rule_add_array.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_int,
                                               ctypes.c_uint, ctypes.c_void_p]
    seccomp.seccomp_syscall_resolve_name.argtypes = [ctypes.c_char_p]
    seccomp.seccomp_load.argtypes = [ctypes.c_void_p]
    seccomp.seccomp_release.argtypes = [ctypes.c_void_p]
    say = lambda text: print(f"sandbox: {text}", file=sys.stderr, flush=True)  # noqa: E731

    if lib.unshare(CLONE_NEWNS) != 0:
        raise OSError(ctypes.get_errno(), "unshare(CLONE_NEWNS)")
    mount(lib, None, "/", None, MS_REC | MS_PRIVATE)
    kept = ("/proc", "/sys", "/dev")  # ProtectSystem=strict leaves these to other settings
    if spec["protect_system"] == "strict":
        for point, flags in mounts():
            if under(point, kept):
                continue
            try:
                # MS_BIND: this mount point only, never the file system (other namespaces).
                mount(lib, None, point, None, MS_REMOUNT | MS_BIND | MS_RDONLY | flags)
            except OSError as e:
                if point == "/":
                    raise
                say(f"left {point} as it was ({e.strerror})")
    for path in spec["private_tmp"]:
        mount(lib, "tmpfs", path, "tmpfs", MS_NOSUID | MS_NODEV, "mode=1777")
    for path in spec["hidden"]:
        mount(lib, "tmpfs", path, "tmpfs", MS_NOSUID | MS_NODEV | MS_NOEXEC, "mode=000")
    for path in spec["writable"]:
        mount(lib, path, path, None, MS_BIND)
        mount(lib, None, path, None, MS_REMOUNT | MS_BIND)
    os.chdir("/")
    os.umask(spec["umask"])
    if spec["drop_capabilities"]:
        for cap in range(64):
            lib.prctl(PR_CAPBSET_DROP, cap, 0, 0, 0)
    os.setgroups([])
    os.setgid(spec["uid"])
    os.setuid(spec["uid"])
    if spec["no_new_privileges"] and lib.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
        raise OSError(ctypes.get_errno(), "PR_SET_NO_NEW_PRIVS")

    # The filters systemd installs, each its own (a call must pass all of them); the allow list
    # last, as it leaves no way to load another.
    if spec["memory_deny_write_execute"]:
        ctx = make_filter(seccomp, SCMP_ACT_ALLOW)
        refuse = scmp_act_errno(errno.EPERM)
        wx = PROT_WRITE | PROT_EXEC
        add_rule(seccomp, ctx, refuse, "mmap", ScmpArgCmp(2, SCMP_CMP_MASKED_EQ, wx, wx))
        for name in ("mprotect", "pkey_mprotect"):
            add_rule(seccomp, ctx, refuse, name,
                     ScmpArgCmp(2, SCMP_CMP_MASKED_EQ, PROT_EXEC, PROT_EXEC))
        add_rule(seccomp, ctx, refuse, "shmat",
                 ScmpArgCmp(2, SCMP_CMP_MASKED_EQ, SHM_EXEC, SHM_EXEC))
        load(seccomp, ctx)
    if spec["address_families"] is not None:
        ctx = make_filter(seccomp, SCMP_ACT_ALLOW)
        refuse = scmp_act_errno(errno.EAFNOSUPPORT)
        for family in range(AF_MAX):
            if family not in spec["address_families"]:
                add_rule(seccomp, ctx, refuse, "socket", ScmpArgCmp(0, SCMP_CMP_EQ, family, 0))
        add_rule(seccomp, ctx, refuse, "socket", ScmpArgCmp(0, SCMP_CMP_GE, AF_MAX, 0))
        load(seccomp, ctx)

    if spec["syscalls"] is not None:
        ctx = make_filter(seccomp, scmp_act_errno(spec["syscall_errno"]))
        for name in spec["syscalls"]:
            add_rule(seccomp, ctx, SCMP_ACT_ALLOW, name)
        load(seccomp, ctx)
    # The sandbox in force, or the test proves nothing.
    ctypes.set_errno(0)
    address = lib.mmap(None, 4096, PROT_READ | PROT_WRITE | PROT_EXEC,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0)
    if address not in (None, ctypes.c_void_p(-1).value) or ctypes.get_errno() != errno.EPERM:
        raise SystemExit("sandbox: a writable and executable mapping was allowed")
    say("a writable and executable mapping is refused (EPERM)")
    for path in spec["read_only"]:
        if not os.statvfs(path).f_flag & os.ST_RDONLY:
            raise SystemExit(f"sandbox: {path} is writable")
    say(f"read-only: {' '.join(spec['read_only'])}")
    for path in spec["writable"]:
        if os.statvfs(path).f_flag & os.ST_RDONLY:
            raise SystemExit(f"sandbox: {path} is read-only")
    try:
        socket.socket(socket.AF_NETLINK, socket.SOCK_RAW)
        raise SystemExit("sandbox: a netlink socket was allowed")
    except OSError as e:
        if e.errno != errno.EAFNOSUPPORT:
            raise
    say("a netlink socket is refused (EAFNOSUPPORT)")
    if spec["syscalls"] is not None:
        # create_module is in no group of @system-service, and gone from the kernel: ENOSYS
        # unfiltered, the unit's SystemCallErrorNumber= through the filter.
        nr = seccomp.seccomp_syscall_resolve_name(b"create_module")
        ctypes.set_errno(0)
        if lib.syscall(nr) != -1 or ctypes.get_errno() != spec["syscall_errno"]:
            raise SystemExit("sandbox: a system call outside SystemCallFilter= was not refused")
        say(f"a system call outside SystemCallFilter= is refused ({len(spec['syscalls'])} allowed)")
    if spec["private_tmp"] and os.listdir("/tmp"):
        raise SystemExit("sandbox: /tmp is not private")
    with open("/proc/self/status") as f:
        caps = dict(re.findall(r"^(Cap\w+):\s*([0-9a-f]+)$", f.read(), flags=re.M))
    if spec["drop_capabilities"] and (int(caps["CapEff"], 16) or int(caps["CapBnd"], 16)):
        raise SystemExit(f"sandbox: capabilities left: {caps}")
    say(f"uid {os.getuid()}, capabilities {caps}")
    sys.stderr.flush()
    os.execve(spec["argv"][0], spec["argv"], spec["env"])


# ------------------------------------------------------------------------- the test (parent) --

def syscall_groups():
    """{"@group": [names and @groups]} as this machine's systemd lists them."""
    text = subprocess.run(["systemd-analyze", "syscall-filter", "--no-pager"],
                          capture_output=True, text=True, check=True).stdout
    groups, current = {}, None
    for line in text.splitlines():
        word = line.strip()
        if not word or word.startswith("#"):
            continue
        if not line.startswith(" "):
            current = groups.setdefault(word, []) if word.startswith("@") else None
        elif current is not None:
            current.append(word.split()[0])
    return groups


def expand_syscalls(items, groups):
    out = set()
    for item in items:
        if item.startswith("@"):
            out |= expand_syscalls(groups[item], groups)
        else:
            out.add(item)
    return out


def allowed_syscalls(unit):
    """SystemCallFilter= as systemd applies it: the first allow list, minus ~ lists."""
    filters = systemd_unit.values(unit, "Service", "SystemCallFilter")
    if not filters:
        return None
    groups = syscall_groups()
    allowed = None
    for entry in filters:
        deny = entry.startswith("~")
        names = expand_syscalls(entry.lstrip("~").split(), groups)
        if deny:
            allowed = (allowed if allowed is not None else set()) - names
        else:
            allowed = (allowed or set()) | names
    return sorted(allowed)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def read_line(stream, pattern, deadline, seen):
    """Reads lines from stream until one matches; returns the match or None at the deadline."""
    buffer = b""
    while time.monotonic() < deadline:
        ready, _, _ = select.select([stream], [], [], 0.2)
        if not ready:
            continue
        chunk = os.read(stream.fileno(), 4096)
        if not chunk:
            return None
        buffer += chunk
        while b"\n" in buffer:
            line, buffer = buffer.split(b"\n", 1)
            seen.append(line.decode(errors="replace"))
            match = re.search(pattern, seen[-1])
            if match:
                return match
    return None


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--launch":
        launch(json.loads(sys.argv[2]))
        return 1
    source_dir, worker, tutorial = (os.path.abspath(a) for a in sys.argv[1:4])
    if os.geteuid() != 0:
        print("SKIP: rebuilding the unit's sandbox needs root (a mount namespace, a user switch)")
        return 77
    if shutil.which("systemd-analyze") is None:
        print("FAIL: systemd-analyze is needed for the unit's SystemCallFilter= groups "
              "(deploy/install-deps.sh installs systemd)")
        return 1

    with open(os.path.join(source_dir, "deploy/systemd/tessera-worker.service.in")) as f:
        unit = systemd_unit.parse_unit(f.read().replace("@TESSERA_WORKER_PATH@", worker))
    service = lambda key: systemd_unit.value(unit, "Service", key)  # noqa: E731
    failures = []
    # The sandbox's state lives beside the test, outside what it hides (/tmp, /home, /root).
    top = tempfile.mkdtemp(prefix="sandbox.", dir=os.getcwd())
    os.chmod(top, 0o755)
    worker_process = None
    try:
        # LoadCredential=: copies owned by the service's user, read-only, in a directory of theirs.
        tls = os.path.join(top, "tls")
        subprocess.run([os.path.join(source_dir, "deploy/tls/make-certs.sh"), tls, "localhost",
                        "127.0.0.1"], check=True, capture_output=True)
        credentials = os.path.join(top, "credentials")
        os.mkdir(credentials)
        sources = {"worker.pem": f"{tls}/localhost/worker.pem",
                   "worker.key": f"{tls}/localhost/worker.key",
                   "tessera.token": f"{tls}/tessera.token"}
        for entry in systemd_unit.values(unit, "Service", "LoadCredential"):
            name, _ = entry.split(":", 1)
            shutil.copy(sources[name], os.path.join(credentials, name))
            os.chown(os.path.join(credentials, name), SERVICE_UID, SERVICE_UID)
            os.chmod(os.path.join(credentials, name), 0o400)
        os.chown(credentials, SERVICE_UID, SERVICE_UID)
        os.chmod(credentials, 0o500)
        # CacheDirectory=, under a cache root that stands for /var/cache (%C).
        cache_root = os.path.join(top, "cache")
        cache = os.path.join(cache_root, service("CacheDirectory"))
        os.makedirs(cache, mode=int(service("CacheDirectoryMode") or "0755", 8))
        os.chown(cache, SERVICE_UID, SERVICE_UID)

        flags = subprocess.run([worker, "--help"], capture_output=True, text=True).stdout
        status_port = free_port() if "--status-listen" in flags else None
        worker_env = ("TESSERA_WORKER_LISTEN=127.0.0.1:0\n"
                      "TESSERA_WORKER_ARGS=--threads 2 --max-sessions 4" +
                      (f" --status-listen 127.0.0.1:{status_port}" if status_port else "") + "\n")
        env = systemd_unit.environment_of(unit, env_files=[worker_env])
        argv = systemd_unit.expand(
            systemd_unit.exec_argv(service("ExecStart")),
            {"d": credentials, "C": cache_root, "H": socket.gethostname()}, env)
        env.update({"PATH": "/usr/local/bin:/usr/bin:/bin", "LANG": "C.UTF-8", "HOME": "/",
                    "CREDENTIALS_DIRECTORY": credentials, "CACHE_DIRECTORY": cache})

        hidden_roots = ["/home", "/root", "/run/user"] if service("ProtectHome") == "yes" else []
        private_tmp = ["/tmp", "/var/tmp"] if service("PrivateTmp") == "yes" else []
        for path in (worker, source_dir):
            if under(path, hidden_roots + private_tmp):
                print(f"note: {path} lies under what the unit hides; those stay visible here")
                hidden_roots = [r for r in hidden_roots if not under(path, [r])]
                private_tmp = [r for r in private_tmp if not under(path, [r])]
        families = {"AF_UNIX": 1, "AF_INET": 2, "AF_INET6": 10}
        spec = {
            "argv": argv, "env": env, "uid": SERVICE_UID,
            "umask": int(service("UMask") or "0022", 8),
            "protect_system": service("ProtectSystem"),
            "private_tmp": private_tmp,
            "hidden": [p for p in hidden_roots if os.path.isdir(p)],
            "writable": [cache],
            "read_only": ["/", "/usr", "/etc", os.path.dirname(worker)],
            "drop_capabilities": unit["Service"].get("CapabilityBoundingSet") == [""],
            "no_new_privileges": service("NoNewPrivileges") == "yes",
            "syscalls": allowed_syscalls(unit),
            "syscall_errno": getattr(errno, service("SystemCallErrorNumber") or "EPERM"),
            "memory_deny_write_execute": service("MemoryDenyWriteExecute") == "yes",
            "address_families": [families[f] for f in " ".join(systemd_unit.values(
                unit, "Service", "RestrictAddressFamilies")).split()] or None,
        }
        print("worker:", " ".join(argv))
        worker_process = subprocess.Popen(
            [sys.executable, os.path.abspath(__file__), "--launch", json.dumps(spec)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        seen = []
        match = read_line(worker_process.stdout, r"tessera-worker listening on (\S+)",
                          time.monotonic() + 30, seen)
        if match is None:
            worker_process.kill()
            _, err = worker_process.communicate()
            print("FAIL: the sandboxed worker did not start:\n" + "\n".join(seen) + err.decode())
            return 1
        address = match.group(1)
        print(f"sandboxed worker listening on {address}")

        # The same image through the sandboxed worker (TLS, token) as on an inproc device.
        images = {}
        for name, devices in (("worker", address), ("inproc", "inproc")):
            images[name] = os.path.join(top, f"{name}.png")
            render_env = dict(os.environ, TESSERA_DEVICES=devices,
                              TESSERA_TLS_CA=f"{tls}/ca.pem",
                              TESSERA_TOKEN_FILE=f"{tls}/tessera.token")
            render_env.pop("TESSERA_TOKEN", None)
            started = time.monotonic()
            render = subprocess.run(render_command(tutorial, images[name]), env=render_env,
                                    capture_output=True, text=True, timeout=120)
            if render.returncode != 0:
                failures.append(f"the render on {devices} failed: {render.stderr}")
            else:
                print(f"rendered on {devices} in {time.monotonic() - started:.1f} s")
        if not failures:
            with open(images["worker"], "rb") as a, open(images["inproc"], "rb") as b:
                if a.read() != b.read():
                    failures.append("the sandboxed worker's image differs from inproc's")
        modules = [f for _, _, files in os.walk(cache) for f in files]
        if not modules:
            failures.append(f"no program module was cached in {cache} (--module-cache)")
        else:
            print(f"{len(modules)} files in the worker's cache directory")

        if status_port:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{status_port}/healthz",
                                            timeout=5) as reply:
                    body = reply.read().decode().strip()
                    if reply.status != 200 or body != "ok":
                        failures.append(f"/healthz answered {reply.status} {body!r}")
                    else:
                        print("/healthz: 200 ok")
            except OSError as e:
                failures.append(f"/healthz on the status port: {e}")
        else:
            print("SKIP (one assertion): this tessera-worker has no --status-listen yet, so "
                  "/healthz was not checked")

        # KillSignal=SIGTERM: a graceful stop, exit 0 (Restart=on-failure would restart others).
        worker_process.send_signal(signal.SIGTERM)
        try:
            _, err = worker_process.communicate(timeout=float(service("TimeoutStopSec") or 90))
        except subprocess.TimeoutExpired:
            worker_process.kill()
            _, err = worker_process.communicate()
            failures.append("the worker did not stop on SIGTERM within TimeoutStopSec")
        err = err.decode(errors="replace")
        print(err.rstrip())
        for line in ("a writable and executable mapping is refused",
                     "a netlink socket is refused", "read-only: ",
                     "a system call outside SystemCallFilter= is refused"):
            if f"sandbox: {line}" not in err:
                failures.append(f"the sandbox did not report '{line}'")
        if worker_process.returncode != 0:
            failures.append(f"the worker exited {worker_process.returncode} on SIGTERM")
    finally:
        if worker_process and worker_process.poll() is None:
            worker_process.kill()
            worker_process.wait()
        shutil.rmtree(top, ignore_errors=True)
    return outcome.report(failures)


if __name__ == "__main__":
    sys.exit(main())
