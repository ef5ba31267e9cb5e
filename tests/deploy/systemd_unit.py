"""Reads systemd unit files the way systemd does, for tests/deploy (systemd.syntax(7))."""

import shlex


def parse_unit(text):
    """Returns {section: {key: [values, in order]}}.

    Lines ending in a backslash continue on the next; '#' and ';' start comment lines; a key given
    again appends; an empty assignment is kept as '' (for list settings it resets what came
    before, which `values` applies).
    """
    sections = {}
    current = None
    pending = ""
    for raw in text.splitlines():
        line = raw.strip()
        if pending:
            line = pending + " " + line
            pending = ""
        if not line or line[0] in "#;":
            continue
        if line.endswith("\\"):
            pending = line[:-1].rstrip()
            continue
        if line.startswith("[") and line.endswith("]"):
            current = sections.setdefault(line[1:-1], {})
            continue
        if current is None or "=" not in line:
            raise ValueError(f"not a unit file line: {raw!r}")
        key, value = line.split("=", 1)
        current.setdefault(key.strip(), []).append(value.strip())
    return sections


def values(unit, section, key):
    """The values of a list setting: assignments after the last empty one."""
    assigned = unit.get(section, {}).get(key, [])
    if "" in assigned:
        assigned = assigned[len(assigned) - assigned[::-1].index(""):]
    return assigned


def value(unit, section, key):
    """The value of a single-valued setting: its last assignment, or None."""
    assigned = unit.get(section, {}).get(key, [])
    return assigned[-1] if assigned else None


def exec_argv(command_line):
    """ExecStart= split into words as systemd splits it (quotes; no shell); prefixes dropped."""
    argv = shlex.split(command_line, posix=True)
    while argv and argv[0][:1] in "-@:+!":
        argv[0] = argv[0][1:]
    return argv


def expand(argv, specifiers, environment):
    """ExecStart= words with %x specifiers and $VAR / ${VAR} expanded as systemd does: ${VAR}
    inside a word, $VAR alone as a word splits at whitespace into words (none when empty)."""
    out = []
    for word in argv:
        if word.startswith("$") and not word.startswith("${") and len(word) > 1:
            out.extend(environment.get(word[1:], "").split())
            continue
        result = ""
        i = 0
        while i < len(word):
            c = word[i]
            if c == "%" and i + 1 < len(word):
                spec = word[i + 1]
                if spec == "%":
                    result += "%"
                elif spec in specifiers:
                    result += specifiers[spec]
                else:
                    raise ValueError(f"specifier %{spec} in {word!r} is not known to this test")
                i += 2
            elif word.startswith("${", i):
                end = word.index("}", i)
                result += environment.get(word[i + 2:end], "")
                i = end + 1
            else:
                result += c
                i += 1
        out.append(result)
    return out


def environment_of(unit, section="Service", env_files=()):
    """Environment= assignments, then the given EnvironmentFile= contents (later wins)."""
    env = {}
    for assignment in unit.get(section, {}).get("Environment", []):
        for item in shlex.split(assignment):
            name, _, val = item.partition("=")
            env[name] = val
    for text in env_files:
        for line in text.splitlines():
            line = line.strip()
            if not line or line[0] in "#;" or "=" not in line:
                continue
            name, _, val = line.partition("=")
            val = val.strip()
            if len(val) >= 2 and val[0] == val[-1] and val[0] in "'\"":
                val = val[1:-1]
            env[name.strip()] = val
    return env
