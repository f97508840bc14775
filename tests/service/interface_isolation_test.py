#!/usr/bin/env python3
"""With a loopback-only configuration, Cyclone DDS neither sends nor receives on any other interface.

vifusiond and `vifusion echo rt/vifusion/odometry` run in a private network namespace that has lo and
one extra interface, a veth end that is up, has an IPv4 address and a live peer, and has IPv6 off so
that the kernel itself stays quiet on it. While odometry flows over lo:
- sending: the veth's transmit counters must not move;
- binding: every UDP socket the two processes hold (`ss -uapn`, printed) must be bound to the device
  lo (ss shows "0.0.0.0%lo:7410"). Cyclone 0.10 itself binds its receive sockets to 0.0.0.0 on all
  interfaces; vifusion binds them to the configured interface (platform/dds socket_confinement.hpp);
- receiving: a datagram sent from the peer namespace to vifusiond's receive port on the veth address
  must be refused by the kernel (ICMP port unreachable: no socket takes it there).

Controls prove each check can see a leak: a plain 0.0.0.0 socket in the same namespace does receive
the same kind of datagram from the peer, and `vifusion echo` configured for the veth (unicast peer at
the other end) makes the transmit counter move with its discovery messages.

usage: interface_isolation_test.py BIN_DIR SIM_DIR WORK_DIR DDS_CONFIG
DDS_CONFIG: the loopback-only configuration under test (systemd/cyclonedds.xml, the installed default).
Needs root (skips otherwise, exit 77); CI runs as root.
"""
import os
import re
import subprocess
import sys
import time

from netns import VethPair, require_root_and_ip, write_unicast_config
from service_harness import Echo, check_odometry, dds_domain_and_partition, fail, main, on_exit, start, stop

BIN, SIM, WORK, DDS_CONFIG = sys.argv[1:5]
MESSAGES = 20
# Cyclone's default port mapping: 7400 + 250·domain + 10 + 2·participant index (+1 for data); the
# configuration allows indices 0..32 (MaxAutoParticipantIndex).
MAX_PARTICIPANT_INDEX = 32


def domain_unicast_ports(domain):
    first = 7400 + 250 * domain + 10
    return range(first, first + 2 * MAX_PARTICIPANT_INDEX + 2)


def check_sockets(table, domain):
    """Fails unless every UDP socket of vifusiond and vifusion is bound to the device lo, on 127.0.0.1 or
    on 0.0.0.0 at a unicast port of `domain`. Returns the ports vifusiond receives on at 0.0.0.0."""
    ours = [line for line in table.splitlines() if re.search(r'users:\(\("vifusion', line)]
    if not ours:
        fail(f"ss -uapn lists no socket of vifusiond or vifusion:\n{table}")
    receive_ports = []
    for line in ours:
        local = line.split()[3]
        address, port = local.rsplit(":", 1)
        host, _, device = address.partition("%")
        if device != "lo":
            fail(f"a DDS socket at {local} is not bound to the device lo, so it hears every interface: {line}")
        if host == "127.0.0.1":
            continue
        if host not in ("0.0.0.0", "*") or int(port) not in domain_unicast_ports(domain):
            fail(f"a DDS socket is bound to {local}, neither loopback nor a domain {domain} receive port: {line}")
        if '"vifusiond"' in line:
            receive_ports.append(int(port))
    if not receive_ports:
        fail("vifusiond holds no receive socket on a domain port")
    return receive_ports


PROBE = """
import socket, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.connect((sys.argv[1], int(sys.argv[2])))
s.settimeout(2.0)
s.send(b"vifusion isolation probe")
try:
    s.recv(64)
except ConnectionRefusedError:
    print("refused"); sys.exit(0)
except socket.timeout:
    pass
print("accepted")
"""


def send_probe(net, port):
    """Sends a datagram from the peer namespace to addr_a:port; "refused" when no socket in ns_a took it
    on the veth (the kernel answered port unreachable), "accepted" otherwise."""
    result = subprocess.run([*net.exec(net.ns_b), sys.executable, "-c", PROBE, net.addr_a, str(port)],
                            capture_output=True, text=True, timeout=30)
    if result.returncode != 0:
        fail(f"the probe from {net.ns_b} failed: {result.stderr.strip()}")
    return result.stdout.strip()


def tx(net):
    counters = net.counters(net.ns_a, net.if_a)["tx"]
    return counters["packets"], counters["bytes"]


def isolation():
    require_root_and_ip()
    net = VethPair()
    on_exit(net.delete)
    net.create()
    work = f"{WORK}/isolation-{os.getpid()}"
    os.makedirs(work, exist_ok=True)
    domain, partition = dds_domain_and_partition("isolation-test")
    in_a = net.exec(net.ns_a)

    before = tx(net)
    odometry = Echo(f"{BIN}/vifusion", "rt/vifusion/odometry", MESSAGES, 40,
                    ["--dds-config", DDS_CONFIG, "--domain", str(domain), "--partition", partition], prefix=in_a)
    # Every frame processed (no real-time replay): on a loaded machine the replay overran the camera
    # ring and the 3 s source ended after 18 processed frames, short of the 20 messages counted here.
    service = start([*in_a, f"{BIN}/vifusiond", "--source", f"dataset:{SIM}", "--out", f"{work}/out",
                     "--realtime", "false", "--dds.config", DDS_CONFIG, "--dds.domain", str(domain),
                     "--dds.partition", partition])
    deadline = time.monotonic() + 45
    while len(odometry.lines) < MESSAGES // 2 and odometry.process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    table = net.udp_sockets(net.ns_a)  # while both run, every DDS socket exists
    print(f"UDP sockets in {net.ns_a} while odometry flows (ss -uapn):\n{table}", flush=True)
    receive_ports = check_sockets(table, domain)
    print(f"every DDS socket is bound to the device lo; vifusiond receives on ports {receive_ports}", flush=True)
    if odometry.wait(45) != 0:
        fail(f"echo received {len(odometry.lines)} of {MESSAGES} odometry messages over lo with {DDS_CONFIG}")
    moved, _ = check_odometry(odometry.lines)
    code = stop(service)
    after = tx(net)
    print(f"{len(odometry.lines)} odometry messages over lo (camera moved {moved * 1000:.1f} mm); "
          f"{net.if_a} tx packets {before[0]} → {after[0]}, bytes {before[1]} → {after[1]}", flush=True)
    if after != before:
        fail(f"DDS configured for lo only sent {after[0] - before[0]} packets ({after[1] - before[1]} bytes) "
             f"on {net.if_a}")
    if code != 0:
        fail(f"vifusiond exited with {code} after SIGTERM")

    # Receiving, with a second run (the kernel's port-unreachable replies to the probes go out on the
    # veth, so they cannot share the transmit check above).
    service = start([*in_a, f"{BIN}/vifusiond", "--source", f"dataset:{SIM}", "--out", f"{work}/out2",
                     "--realtime", "false", "--dds.config", DDS_CONFIG, "--dds.domain", str(domain),
                     "--dds.partition", partition])
    # vifusiond binds its DDS sockets to lo right after Cyclone creates them: on a loaded machine ss can list one in
    # between. Wait for the steady state (its sockets there, none of them unbound); a socket still unbound at the
    # deadline fails below.
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        table = net.udp_sockets(net.ns_a)
        daemon_sockets = [line for line in table.splitlines() if '"vifusiond"' in line]
        if len(daemon_sockets) >= 2 and all("%lo:" in line for line in daemon_sockets):
            break
        time.sleep(0.1)
    receive_ports = check_sockets(table, domain)
    for port in receive_ports:
        verdict = send_probe(net, port)
        print(f"a datagram from {net.ns_b} to {net.addr_a}:{port} while vifusiond listens there: {verdict}",
              flush=True)
        if verdict != "refused":
            fail(f"vifusiond's receive socket on port {port} took a datagram that arrived on {net.if_a}")
    stop(service)

    # Control: the probe does see a socket that listens on every interface.
    listener = start([*in_a, sys.executable, "-c",
                      "import socket, sys; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); "
                      "s.bind(('0.0.0.0', int(sys.argv[1]))); s.settimeout(20); print(s.recv(64).decode(), flush=True)",
                      str(receive_ports[0])], stdout=subprocess.PIPE, text=True)
    time.sleep(0.5)
    verdict = send_probe(net, receive_ports[0])
    heard = listener.communicate(timeout=30)[0].strip()
    print(f"control: a plain 0.0.0.0 socket on port {receive_ports[0]}: probe {verdict}, it heard '{heard}'", flush=True)
    if verdict != "accepted" or "probe" not in heard:
        fail("the control listener bound to 0.0.0.0 did not receive the probe: the probe cannot see a leak")

    # Control: the same counter sees DDS when DDS is configured to use that interface.
    after = tx(net)
    veth_config = write_unicast_config(f"{work}/veth.xml", net.if_a, net.addr_b)
    probe = start([*in_a, f"{BIN}/vifusion", "echo", "rt/vifusion/odometry", "--count", "1", "--timeout", "2",
                   "--dds-config", veth_config, "--domain", str(domain), "--partition", partition])
    probe.wait(30)  # nobody publishes there: it times out, having sent its discovery messages
    control = tx(net)
    print(f"control: vifusion echo configured for {net.if_a} sent {control[0] - after[0]} packets "
          f"({control[1] - after[1]} bytes) on it", flush=True)
    if control[0] <= after[0]:
        fail(f"the control run configured for {net.if_a} sent nothing on it: the counter would not see a leak")


main({"isolation": isolation}, "isolation")
