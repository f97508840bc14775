"""Two private network namespaces joined by a veth pair: "a second machine", or "an extra interface",
for the service tests, without touching the host's own interfaces. Needs root and iproute2 (`ip`).

The veth ends are created directly inside their namespaces (never in the host's), get one /30 of
10.231.0.0/16 and have IPv6 disabled before they come up: no router solicitations, DAD or MLD
reports, so the kernel itself sends nothing on them and their counters move only for what the test's
processes send. Names carry this process's id, so parallel runs never collide; namespaces that a
killed run left behind (ctest's SIGKILL at a timeout cannot be caught) are removed by the next run
that finds their process gone.
"""
import json
import os
import random
import re
import shutil
import subprocess

from service_harness import fail, skip

PREFIX = "vifusion-test-"
STALE = re.compile(re.escape(PREFIX) + r"(\d+)-[0-9a-f]+-[ab]")


def require_root_and_ip():
    if os.geteuid() != 0:
        skip("network namespaces need root (CI runs as root): run ctest as root to include this test")
    if shutil.which("ip") is None:
        skip("iproute2's `ip` is not installed (Debian package iproute2)")


def ip(*args):
    result = subprocess.run(["ip", *args], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"`ip {' '.join(args)}` failed ({result.returncode}): {result.stderr.strip()}")
    return result.stdout


def remove_stale_namespaces():
    for name in os.listdir("/run/netns") if os.path.isdir("/run/netns") else []:
        match = STALE.fullmatch(name)
        if match and not os.path.exists(f"/proc/{match[1]}"):
            print(f"removing namespace {name} left behind by a killed run", flush=True)
            subprocess.run(["ip", "netns", "del", name], capture_output=True)


class VethPair:
    """Namespaces ns_a and ns_b, each with lo up and one veth end (if_a, if_b) at addr_a, addr_b."""

    def __init__(self):
        token = f"{os.getpid()}-{random.getrandbits(24):06x}"
        self.ns_a, self.ns_b = f"{PREFIX}{token}-a", f"{PREFIX}{token}-b"
        suffix = f"{random.getrandbits(32):08x}"  # interface names: at most 15 characters
        self.if_a, self.if_b = f"vfa{suffix}", f"vfb{suffix}"
        subnet = f"10.231.{random.randrange(256)}"
        host = 4 * random.randrange(64)
        self.addr_a, self.addr_b = f"{subnet}.{host + 1}", f"{subnet}.{host + 2}"
        self._created = []

    def create(self):
        remove_stale_namespaces()
        for ns in (self.ns_a, self.ns_b):
            ip("netns", "add", ns)
            self._created.append(ns)
        ip("link", "add", self.if_a, "netns", self.ns_a, "type", "veth", "peer", "name", self.if_b, "netns", self.ns_b)
        for ns, interface, address in ((self.ns_a, self.if_a, self.addr_a), (self.ns_b, self.if_b, self.addr_b)):
            ip("netns", "exec", ns, "sh", "-c", f"echo 1 > /proc/sys/net/ipv6/conf/{interface}/disable_ipv6")
            ip("-n", ns, "address", "add", f"{address}/30", "dev", interface)
            ip("-n", ns, "link", "set", "lo", "up")
            ip("-n", ns, "link", "set", interface, "up")
        print(f"namespaces {self.ns_a} ({self.if_a} {self.addr_a}) and {self.ns_b} ({self.if_b} {self.addr_b})",
              flush=True)
        return self

    def delete(self):
        """Removes the namespaces (and with them the veth pair); safe to call on any path."""
        while self._created:
            subprocess.run(["ip", "netns", "del", self._created.pop()], capture_output=True)

    @staticmethod
    def exec(ns):
        """The command prefix that runs a program inside namespace `ns`."""
        return ["ip", "netns", "exec", ns]

    @staticmethod
    def counters(ns, interface):
        """The interface's kernel counters, /sys/class/net/IF/statistics as seen inside `ns`:
        {"tx": {"packets": …, "bytes": …, …}, "rx": {…}}."""
        (link,) = json.loads(ip("-n", ns, "-s", "-j", "link", "show", "dev", interface))
        return link["stats64"]

    @staticmethod
    def udp_sockets(ns):
        """`ss -uapn` inside `ns`: every UDP socket with its local address and owning process."""
        result = subprocess.run(["ip", "netns", "exec", ns, "ss", "-uapn"], capture_output=True, text=True)
        if result.returncode != 0:
            fail(f"ss -uapn in {ns} failed: {result.stderr.strip()}")
        return result.stdout


def write_unicast_config(path, interface, peer):
    """A Cyclone DDS configuration that uses only `interface`, no multicast, and discovers by unicast to
    `peer` (platform.md: "DDS across network namespaces")."""
    with open(path, "w") as f:
        f.write(f"""<?xml version="1.0" encoding="UTF-8"?>
<CycloneDDS xmlns="https://cdds.io/config">
  <Domain id="any">
    <General>
      <Interfaces><NetworkInterface name="{interface}"/></Interfaces>
      <AllowMulticast>false</AllowMulticast>
    </General>
    <Discovery>
      <ParticipantIndex>auto</ParticipantIndex>
      <MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>
      <Peers><Peer address="{peer}"/></Peers>
    </Discovery>
  </Domain>
</CycloneDDS>
""")
    return path
