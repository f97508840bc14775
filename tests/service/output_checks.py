"""What a SIGKILL may leave in an output directory, checked (issue 22 item 5): every file is complete — the previous
version or the new one, never partial (core/atomic_file.hpp). Shared by crash_safety_test.py and
systemd_restart_test.py."""
import json
import os
import re
import subprocess

from service_harness import fail

PLY_TYPE_BYTES = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8}


def check_text_table(path, separator):
    """Every row has the header's number of fields, and the file ends with a newline."""
    with open(path) as f:
        text = f.read()
    if not text.endswith("\n"):
        return "does not end with a newline"
    lines = [line for line in text.splitlines() if line]
    header = next((line for line in lines if line.startswith("#")), None)
    rows = [line for line in lines if not line.startswith("#")]
    width = len(re.split(separator, header.lstrip("#").strip())) if header else len(re.split(separator, rows[0]))
    for number, row in enumerate(rows):
        if len(re.split(separator, row.strip())) != width:
            return f"row {number} has {len(re.split(separator, row.strip()))} fields, the header {width}"
    return None


def check_ply(path):
    """The binary body holds exactly the vertices the header promises."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        return "no PLY header"
    header = data[:end].decode()
    count = int(re.search(r"element vertex (\d+)", header).group(1))
    stride = sum(PLY_TYPE_BYTES[t] for t in re.findall(r"property (\w+) \w+", header))
    body = len(data) - end - len("end_header\n")
    return None if body == count * stride else f"{body} bytes of vertices, the header promises {count} × {stride}"


def check_map_file(path, bin_dir):
    result = subprocess.run([os.path.join(bin_dir, "vifusion"), "map", "info", path], capture_output=True, text=True)
    return None if result.returncode == 0 else result.stderr.strip()


def check_json(path):
    try:
        with open(path) as f:
            json.load(f)
    except ValueError as error:
        return str(error)
    return None


CHECKS = {"trajectory.txt": lambda p, _: check_text_table(p, r"\s+"), "frames.csv": lambda p, _: check_text_table(p, ","),
          "states.csv": lambda p, _: check_text_table(p, ","), "report.json": lambda p, _: check_json(p),
          "map.ply": lambda p, _: check_ply(p), "map.vifmap": check_map_file}


def check_directory(out, known, after, bin_dir):
    """Every file is one of `known` outputs (or, after a kill between a link and its rename, a complete
    '<output>.tmp') and passes its check (`vifusion map info` from bin_dir for map files). Returns the outputs
    present."""
    present = []
    for name in sorted(os.listdir(out)):
        base = name[:-len(".tmp")] if name.endswith(".tmp") else name
        if base not in known:
            fail(f"{after}: unexpected file {name} in {out}")
        problem = CHECKS[base](os.path.join(out, name), bin_dir)
        if problem:
            fail(f"{after}: {name} is partial or corrupt: {problem}")
        present.append(name)
    return present
