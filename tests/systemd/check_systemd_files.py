#!/usr/bin/env python3
"""Checks of the files in systemd/, run by ctest (tests/systemd/CMakeLists.txt, label `systemd`).

  verify    UNIT                    systemd-analyze verify; any message about the unit is a failure
  security  UNIT --max E --allow-gap NAME... --json OUT
                                    systemd-analyze security --offline=yes: overall exposure <= E and no
                                    unmet setting outside the listed deliberate gaps; writes OUT (JSON)
  udevadm   RULES [--sysusers FILE]  udev's own rule parser (udevadm test in a private mount namespace
                                    that sees only RULES, and the groups FILE creates); any message
                                    about the file is a failure
  udev-lint RULES [--groups G...] [--require-usb-id VVVV:PPPP...]
                                    a stricter syntax check plus this project's policy (mode 0660, no
                                    world bits, known groups, lower-case USB ids, no OWNER/RUN)
  sysusers-tmpfiles SYSUSERS TMPFILES
                                    systemd-sysusers then systemd-tmpfiles --create into a scratch root;
                                    checks the user, groups, directories, owners and modes
  dds-config XML                    the shipped Cyclone DDS default keeps DDS on this machine: well-formed,
                                    Cyclone's namespace, only interface lo, multicast off, loopback peers
  install BUILD_DIR DESTDIR --cmake CMAKE --expect PATH...
                                    cmake --install BUILD_DIR --component service with DESTDIR: every
                                    expected PATH is installed (and each .xml passes dds-config)

--expect-failure REGEX (before the command) inverts a check for the negative tests: it passes only if
the check fails with a message matching REGEX. Exit status 77 means "skipped" (ctest SKIP_RETURN_CODE).
Debian 12 tools: systemd 252 (no `udevadm verify` yet, which came with 253).
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

SKIP = 77


class CheckFailed(Exception):
    pass


class Skipped(Exception):
    pass


def run(cmd, **kwargs):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kwargs)
    return proc.returncode, proc.stdout


def require_tool(name):
    path = shutil.which(name)
    if not path:
        raise CheckFailed(f"{name} not found: install the packages in .ci/debian-packages.txt")
    return path


# --- systemd-analyze verify -------------------------------------------------------------------------

# Dependencies of our units (modprobe@.service, network-online.target, ...) are loaded too; messages
# that name one of the distribution's own unit files are not about our units and are only shown.
FOREIGN_UNIT_FILE = re.compile(r"^(/usr)?/lib/systemd/|^/etc/systemd/|^/run/systemd/")


def check_verify(unit):
    analyze = require_tool("systemd-analyze")
    name = os.path.basename(unit)
    # --recursive-errors=no: judge only this unit; with it systemd 252 also fails on unknown keys.
    # --man=no: Documentation= man pages need not be installed in CI.
    rc, out = run([analyze, "verify", "--recursive-errors=no", "--man=no", unit])
    ours, foreign = [], []
    for line in out.splitlines():
        if not line.strip():
            continue
        (foreign if FOREIGN_UNIT_FILE.match(line) and name not in line else ours).append(line)
    for line in foreign:
        print(f"note (not about {name}): {line}")
    for line in ours:
        print(line)
    if rc != 0 or ours:
        raise CheckFailed(f"systemd-analyze verify {name}: exit status {rc}, {len(ours)} message(s) "
                          "(every message counts: unknown keys and bad values are only warnings to systemd)")
    print(f"systemd-analyze verify {name}: clean")


# --- systemd-analyze security ------------------------------------------------------------------------

OVERALL = re.compile(r"Overall exposure level for (\S+): ([0-9]+\.[0-9]) (\S+)")


def check_security(unit, max_exposure, allowed_gaps, json_out):
    analyze = require_tool("systemd-analyze")
    name = os.path.basename(unit)
    threshold_tenths = int(round(max_exposure * 10))
    # systemd's own comparison (exposure in tenths) decides, the text gives the figure to record.
    rc, text = run([analyze, "security", "--offline=yes", f"--threshold={threshold_tenths}", "--no-pager", unit])
    match = OVERALL.search(text)
    if not match:
        print(text)
        raise CheckFailed(f"systemd-analyze security {name}: no overall exposure in its output")
    exposure, level = float(match.group(2)), match.group(3)
    rc_json, details = run([analyze, "security", "--offline=yes", "--json=short", "--no-pager", unit])
    try:
        settings = json.loads(details.strip().splitlines()[-1])
    except (ValueError, IndexError):
        print(details)
        raise CheckFailed(f"systemd-analyze security --json=short {name}: output is not JSON")
    gaps = [s for s in settings if s.get("exposure") not in (None, "0.0") and s.get("set") is False]
    gap_names = [s["name"] for s in gaps]
    unexpected = [s for s in gaps if s["name"] not in allowed_gaps]
    stale = [g for g in allowed_gaps if g not in gap_names]
    version = run([analyze, "--version"])[1].splitlines()[0]
    record = {
        "unit": name,
        "exposure": exposure,
        "level": level,
        "max_exposure": max_exposure,
        "systemd": version,
        "deliberate_gaps": [{"name": s["name"], "exposure": float(s["exposure"]), "why_unmet": s["description"]}
                            for s in gaps if s["name"] in allowed_gaps],
        "unexpected_gaps": [{"name": s["name"], "exposure": float(s["exposure"]), "why_unmet": s["description"]}
                            for s in unexpected],
    }
    with open(json_out, "w", encoding="utf-8") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    print(f"{name}: exposure {exposure} {level} (max {max_exposure}), recorded in {json_out}")
    for s in gaps:
        print(f"  {'gap' if s['name'] in allowed_gaps else 'UNEXPECTED'} {s['exposure']} {s['name']}: {s['description']}")
    for g in stale:
        print(f"  note: {g} is listed as a deliberate gap but is met now; drop it from the list")
    problems = []
    if rc != 0 or exposure > max_exposure:
        problems.append(f"exposure {exposure} is above {max_exposure}")
    if unexpected:
        problems.append("hardening missing: " + ", ".join(s["name"] for s in unexpected))
    if problems:
        raise CheckFailed(f"systemd-analyze security {name}: " + "; ".join(problems))


# --- udev: udev's own parser -------------------------------------------------------------------------

# Every directory udev 252 reads rules from, hidden behind empty tmpfs mounts so that only the file under
# test is parsed and nothing of the host's rules, database (/run/udev) or devices is touched. The event
# is simulated on the loopback interface, which has no device node. udev resolves GROUP= names when it
# loads the rules and drops unknown ones, so /etc/group is shown with the sysusers.d groups added, as on
# an installed system where systemd-sysusers ran before udev reloaded its rules.
UDEVADM_SANDBOX = r"""
set -e
mount --make-rprivate /
for d in /etc/udev/rules.d /run/udev /lib/udev/rules.d /usr/lib/udev/rules.d /usr/local/lib/udev/rules.d; do
  if [ -d "$d" ]; then mount -t tmpfs -o mode=0755 tmpfs "$d"; fi
done
cp "$1" /etc/udev/rules.d/
mount --bind "$2" /etc/group
exec udevadm test --action=add /sys/class/net/lo
"""


def sysusers_groups(sysusers):
    """Group names a sysusers.d file creates (g lines, and u lines' own group)."""
    names = []
    with open(sysusers, encoding="utf-8") as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 2 and fields[0] in ("g", "u"):
                names.append(fields[1])
    return names


def check_udevadm(rules, sysusers):
    require_tool("udevadm")
    unshare = require_tool("unshare")
    name = os.path.basename(rules)
    probe_rc, probe = run([unshare, "--mount", "true"])
    if probe_rc != 0:
        raise Skipped(f"cannot make a private mount namespace here (needs root): {probe.strip()}")
    with open("/etc/group", encoding="utf-8") as f:
        group_lines = [l.rstrip("\n") for l in f if l.strip()]
    present = {l.split(":")[0] for l in group_lines}
    used = {int(l.split(":")[2]) for l in group_lines}
    gid = 999
    for group in sysusers_groups(sysusers) if sysusers else []:
        if group not in present:
            while gid in used:
                gid -= 1
            group_lines.append(f"{group}:x:{gid}:")
            used.add(gid)
    with tempfile.NamedTemporaryFile("w", prefix="vifusion-group-", delete=False) as g:
        g.write("\n".join(group_lines) + "\n")
    try:
        rc, out = run([unshare, "--mount", "sh", "-c", UDEVADM_SANDBOX, "sh", os.path.abspath(rules), g.name])
    finally:
        os.unlink(g.name)
    read = f"Reading rules file: /etc/udev/rules.d/{name}"
    if read not in out:
        print(out)
        raise CheckFailed(f"udevadm test did not read {name} (exit status {rc})")
    messages = [line for line in out.splitlines() if name in line and line.strip() != read]
    for line in messages:
        print(line)
    if rc != 0 or messages:
        raise CheckFailed(f"udev 252's parser: {len(messages)} message(s) about {name}, exit status {rc}")
    print(f"udev 252's parser read {name} without a message")


# --- udev: strict syntax and policy ------------------------------------------------------------------

MATCH, ASSIGN = {"==", "!="}, {"=", "+=", "-=", ":="}
# key: (attribute in braces: "no" | "required" | "optional", operators udev 252 accepts for it)
UDEV_KEYS = {
    "ACTION": ("no", MATCH), "DEVPATH": ("no", MATCH), "KERNEL": ("no", MATCH),
    "SUBSYSTEM": ("no", MATCH), "DRIVER": ("no", MATCH), "KERNELS": ("no", MATCH),
    "SUBSYSTEMS": ("no", MATCH), "DRIVERS": ("no", MATCH), "TAGS": ("no", MATCH), "RESULT": ("no", MATCH),
    "ATTRS": ("required", MATCH), "CONST": ("required", MATCH), "TEST": ("optional", MATCH),
    "PROGRAM": ("no", MATCH | {"="}), "IMPORT": ("required", MATCH | {"="}),
    "ATTR": ("required", MATCH | {"="}), "SYSCTL": ("required", MATCH | {"="}),
    "ENV": ("required", MATCH | {"=", "+=", ":="}), "TAG": ("no", MATCH | {"=", "+=", "-="}),
    "NAME": ("no", MATCH | {"=", ":="}), "SYMLINK": ("no", MATCH | ASSIGN),
    "OWNER": ("no", {"=", ":="}), "GROUP": ("no", {"=", ":="}), "MODE": ("no", {"=", ":="}),
    "SECLABEL": ("required", {"=", "+=", ":="}), "RUN": ("optional", {"=", "+=", ":="}),
    "OPTIONS": ("no", {"=", "+=", ":="}), "LABEL": ("no", {"="}), "GOTO": ("no", {"="}),
}
PAIR = re.compile(r'(?P<key>[A-Za-z_]+)(\{(?P<attr>[^}]*)\})?\s*(?P<op>==|!=|\+=|-=|:=|=)\s*'
                  r'(?P<e>e?)"(?P<value>(?:[^"\\]|\\.)*)"')
USB_ID_ATTRS = {"idVendor", "idProduct"}


def lint_rules(path, groups, required_ids):
    errors = []
    with open(path, encoding="utf-8") as f:
        physical = f.read().split("\n")
    # Join continuation lines (a trailing backslash), keeping the first line's number.
    lines, pending, start = [], "", 0
    for number, text in enumerate(physical, 1):
        if not pending:
            start = number
        if text.endswith("\\"):
            pending += text[:-1]
            continue
        lines.append((start, pending + text))
        pending = ""
    if pending:
        errors.append(f"{path}:{start}: the file ends inside a continued line")
    labels, gotos, granted = set(), [], []
    for number, text in lines:
        stripped = text.strip()
        if not stripped or stripped.startswith("#"):
            continue
        where = f"{path}:{number}"
        pairs, pos, first = [], 0, True
        while pos < len(stripped):
            if not first:
                sep = re.match(r"\s*,\s*", stripped[pos:])
                if not sep:
                    errors.append(f"{where}: expected ',' before '{stripped[pos:].lstrip()[:20]}'")
                    break
                pos += sep.end()
                if pos == len(stripped):
                    break  # a trailing comma is accepted by udev
            m = PAIR.match(stripped, pos)
            if not m:
                errors.append(f"{where}: not a KEY{{attr}}OP\"value\" pair: '{stripped[pos:pos + 30]}'")
                break
            pairs.append(m)
            pos, first = m.end(), False
        if not pairs:
            continue
        matches, assigns = {}, {}
        for m in pairs:
            key, attr, op, value = m.group("key"), m.group("attr"), m.group("op"), m.group("value")
            spec = UDEV_KEYS.get(key)
            if spec is None:
                errors.append(f"{where}: unknown key '{key}'")
                continue
            needs_attr, ops = spec
            if needs_attr == "required" and not attr:
                errors.append(f"{where}: {key} needs an attribute in braces, {key}{{...}}")
            if needs_attr == "no" and attr is not None:
                errors.append(f"{where}: {key} takes no attribute, found {key}{{{attr}}}")
            if op not in ops:
                errors.append(f"{where}: operator '{op}' is not valid for {key} (valid: {' '.join(sorted(ops))})")
            if attr in USB_ID_ATTRS and key in ("ATTR", "ATTRS"):
                if re.search(r"[A-F]", value):
                    errors.append(f"{where}: {key}{{{attr}}}==\"{value}\": sysfs USB ids are lower-case hex "
                                  "and the match is case-sensitive")
                elif not re.fullmatch(r"[0-9a-f]{4}", value) and not re.search(r"[*?\[|]", value):
                    errors.append(f"{where}: {key}{{{attr}}}==\"{value}\" is not a 4-digit hex USB id")
            full = f"{key}{{{attr}}}" if attr else key
            (matches if op in MATCH else assigns)[full] = (op, value)
            if key == "LABEL":
                labels.add(value)
            if key == "GOTO":
                gotos.append((where, value))
        if not matches and not {"LABEL", "GOTO"} & set(assigns):
            errors.append(f"{where}: a rule without a match applies to every device")
        # Policy: devices reach the service through groups; mode 0660 style, nothing for "other".
        if "OWNER" in assigns:
            errors.append(f"{where}: OWNER= is not used here; grant devices to a group")
        if "RUN" in assigns or any(k.startswith("RUN{") for k in assigns):
            errors.append(f"{where}: RUN is not used here; rules must not start programs")
        if "MODE" in assigns:
            mode = assigns["MODE"][1]
            if not re.fullmatch(r"0?[0-7]{3}", mode):
                errors.append(f"{where}: MODE=\"{mode}\" is not an octal mode")
            elif int(mode, 8) & 0o007:
                errors.append(f"{where}: MODE=\"{mode}\" gives access to every user; use a group and 0660")
            if "GROUP" not in assigns:
                errors.append(f"{where}: MODE= without GROUP= leaves the device to root only")
        if "GROUP" in assigns:
            group = assigns["GROUP"][1]
            if groups and group not in groups:
                errors.append(f"{where}: GROUP=\"{group}\" is not one of the service's groups ({' '.join(groups)})")
            if "MODE" not in assigns:
                errors.append(f"{where}: GROUP= without MODE= relies on udev's default mode; say MODE=\"0660\"")
        subsystem = matches.get("SUBSYSTEM", ("", ""))[1]
        vendor = (matches.get("ATTR{idVendor}") or matches.get("ATTRS{idVendor}") or ("", ""))[1]
        product = (matches.get("ATTR{idProduct}") or matches.get("ATTRS{idProduct}") or ("", ""))[1]
        if vendor and product and "GROUP" in assigns and "MODE" in assigns:
            granted.append((subsystem, f"{vendor}:{product}"))
    for where, label in gotos:
        if label not in labels:
            errors.append(f"{where}: GOTO=\"{label}\" has no LABEL=\"{label}\" in this file")
    for usb_id in required_ids:
        for subsystem in ("usb", "video4linux"):
            if (subsystem, usb_id) not in granted:
                errors.append(f"{path}: no rule grants {subsystem} device {usb_id} to a group with a mode")
    for e in errors:
        print(e)
    if errors:
        raise CheckFailed(f"{path}: {len(errors)} problem(s)")
    print(f"{path}: {sum(1 for _, t in lines if t.strip() and not t.strip().startswith('#'))} rules, syntax and policy OK")


# --- sysusers.d and tmpfiles.d -----------------------------------------------------------------------

def check_sysusers_tmpfiles(sysusers, tmpfiles):
    sysusers_tool = require_tool("systemd-sysusers")
    tmpfiles_tool = require_tool("systemd-tmpfiles")
    with tempfile.TemporaryDirectory(prefix="vifusion-sysroot-") as root:
        os.makedirs(os.path.join(root, "etc"))
        rc, out = run([sysusers_tool, f"--root={root}", os.path.abspath(sysusers)])
        print(out, end="")
        if rc != 0 or "Failed" in out or "Invalid" in out:
            raise CheckFailed(f"systemd-sysusers {sysusers}: exit status {rc}")
        users = {l.split(":")[0]: l.split(":") for l in open(os.path.join(root, "etc/passwd"))}
        groups = {l.split(":")[0]: l.split(":") for l in open(os.path.join(root, "etc/group"))}
        if "vifusion" not in users:
            raise CheckFailed("sysusers did not create user vifusion")
        missing = [g for g in ("vifusion", "video", "render", "plugdev", "gpio") if g not in groups]
        if missing:
            raise CheckFailed(f"sysusers did not create group(s) {', '.join(missing)}")
        uid, gid = int(users["vifusion"][2]), int(users["vifusion"][3])
        if uid >= 1000 or users["vifusion"][6].strip() not in ("/usr/sbin/nologin", "/sbin/nologin"):
            raise CheckFailed(f"vifusion must be a system user without a login shell: {':'.join(users['vifusion'])}")
        rc, out = run([tmpfiles_tool, f"--root={root}", "--create", os.path.abspath(tmpfiles)])
        print(out, end="")
        if rc != 0 or out.strip():
            raise CheckFailed(f"systemd-tmpfiles --create {tmpfiles}: exit status {rc}")
        expected = {"etc/vifusion": (0o755, 0, 0), "var/lib/vifusion": (0o750, uid, gid),
                    "var/log/vifusion": (0o750, uid, gid)}
        for rel, (mode, owner, group) in expected.items():
            st = os.stat(os.path.join(root, rel))
            got = (st.st_mode & 0o7777, st.st_uid, st.st_gid)
            if got != (mode, owner, group):
                raise CheckFailed(f"/{rel}: mode {oct(got[0])} owner {got[1]}:{got[2]}, expected {oct(mode)} {owner}:{group}")
        print(f"sysusers: user vifusion ({uid}:{gid}) and its groups; tmpfiles: {', '.join('/' + r for r in expected)}")


# --- the default Cyclone DDS configuration ------------------------------------------------------------

def check_dds_config(path):
    try:
        root = ElementTree.parse(path).getroot()
    except (ElementTree.ParseError, OSError) as e:
        raise CheckFailed(f"{path}: not a readable XML file: {e}")

    def elements(name):  # with or without Cyclone's namespace (https://cdds.io/config): it accepts both
        return [e for e in root.iter() if e.tag.rsplit("}", 1)[-1] == name]

    if not elements("CycloneDDS"):
        raise CheckFailed(f"{path}: no CycloneDDS element: not a Cyclone DDS configuration")
    interfaces = [e.get("name") for e in elements("NetworkInterface")]
    if not interfaces:
        raise CheckFailed(f"{path}: names no NetworkInterface: Cyclone would pick the machine's outside interface")
    for name in interfaces:
        if name != "lo":
            raise CheckFailed(f"{path}: names interface '{name}': the shipped default must use lo only")
    multicast = [(e.text or "").strip() for e in elements("AllowMulticast")]
    if multicast != ["false"]:
        raise CheckFailed(f"{path}: AllowMulticast is {multicast or 'unset (default: on)'}, expected false")
    peers = [e.get("address") or "" for e in elements("Peer")]
    if not peers or any(not p.startswith("127.") for p in peers):
        raise CheckFailed(f"{path}: peers {peers}: unicast discovery needs loopback peers (127.0.0.1) only")
    print(f"{path}: interfaces {interfaces}, AllowMulticast false, peers {peers}")


# --- cmake --install -----------------------------------------------------------------------------------

def check_install(build_dir, destdir, cmake, expected):
    shutil.rmtree(destdir, ignore_errors=True)
    rc, out = run([cmake, "--install", build_dir, "--component", "service"], env={**os.environ, "DESTDIR": destdir})
    print(out, end="")
    if rc != 0:
        raise CheckFailed(f"cmake --install {build_dir} --component service: exit status {rc}")
    installed = sorted("/" + os.path.relpath(os.path.join(d, f), destdir) for d, _, files in os.walk(destdir)
                       for f in files)
    missing = [path for path in expected if path not in installed]
    if missing:
        raise CheckFailed(f"not installed: {', '.join(missing)} (installed: {', '.join(installed)})")
    for path in expected:
        if path.endswith(".xml"):
            check_dds_config(destdir + path)
    # The installed configuration must be one the installed daemon accepts (a typo stops the service).
    daemons = [path for path in expected if path.endswith("/vifusiond")]
    for config in (path for path in expected if path.endswith(".yaml")):
        for daemon in daemons:
            rc, out = run([destdir + daemon, "--config", destdir + config, "--dump-config"])
            if rc != 0:
                raise CheckFailed(f"{config}: the installed {daemon} rejects it (exit {rc}): {out.strip()}")
            print(f"{config}: accepted by {daemon}")
    print(f"installed {len(installed)} files, the {len(expected)} expected among them")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--expect-failure", metavar="REGEX")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("verify"); p.add_argument("unit")
    p = sub.add_parser("security"); p.add_argument("unit")
    p.add_argument("--max", type=float, required=True); p.add_argument("--json", required=True)
    p.add_argument("--allow-gap", action="append", default=[])
    p = sub.add_parser("udevadm"); p.add_argument("rules"); p.add_argument("--sysusers")
    p = sub.add_parser("udev-lint"); p.add_argument("rules")
    p.add_argument("--groups", nargs="*", default=[]); p.add_argument("--require-usb-id", nargs="*", default=[])
    p = sub.add_parser("sysusers-tmpfiles"); p.add_argument("sysusers"); p.add_argument("tmpfiles")
    p = sub.add_parser("dds-config"); p.add_argument("xml")
    p = sub.add_parser("install"); p.add_argument("build_dir"); p.add_argument("destdir")
    p.add_argument("--cmake", required=True); p.add_argument("--expect", nargs="+", required=True)
    args = parser.parse_args()

    import contextlib
    import io
    captured = io.StringIO()
    try:
        with contextlib.redirect_stdout(captured):
            if args.command == "verify":
                check_verify(args.unit)
            elif args.command == "security":
                check_security(args.unit, args.max, args.allow_gap, args.json)
            elif args.command == "udevadm":
                check_udevadm(args.rules, args.sysusers)
            elif args.command == "udev-lint":
                lint_rules(args.rules, args.groups, args.require_usb_id)
            elif args.command == "sysusers-tmpfiles":
                check_sysusers_tmpfiles(args.sysusers, args.tmpfiles)
            elif args.command == "dds-config":
                check_dds_config(args.xml)
            else:
                check_install(args.build_dir, args.destdir, args.cmake, args.expect)
        failure = None
    except CheckFailed as e:
        failure = str(e)
    except Skipped as e:
        print(captured.getvalue(), end="")
        print(f"SKIPPED: {e}")
        return SKIP
    output = captured.getvalue() + (f"FAILED: {failure}\n" if failure else "")
    print(output, end="")
    if args.expect_failure is None:
        return 1 if failure else 0
    if failure is None:
        print(f"expected a failure matching /{args.expect_failure}/, but the check passed")
        return 1
    if not re.search(args.expect_failure, output):
        print(f"the check failed, but not with a message matching /{args.expect_failure}/")
        return 1
    print(f"failed as expected (/{args.expect_failure}/)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
