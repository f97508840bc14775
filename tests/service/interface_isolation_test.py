#!/usr/bin/env python3
"""With a loopback-only configuration, Cyclone DDS sends nothing on any other interface.

vifusiond and `vifusion echo rt/vifusion/odometry` run in a private network namespace that has lo and
one extra interface, a veth end that is up, has an IPv4 address and a live peer, and has IPv6 off so
that the kernel itself stays quiet on it. While odometry flows over lo, the veth's transmit counters
must not move, and the UDP sockets the two processes hold (`ss -uapn`, printed) must be bound to
127.0.0.1 (the transmit sockets) or to 0.0.0.0 on the domain's discovery/data ports.

The 0.0.0.0 sockets are Cyclone 0.10's unicast receive sockets: it binds them to the wildcard address
whatever the configuration says, and has no option to bind them to an interface's address. What
Cyclone can be held to — and this test holds — is that it never SENDS elsewhere; what it may receive
from other interfaces is decided outside it, by systemd's IPAddressAllow=/IPAddressDeny= in the units.

A control run then proves the counters see DDS traffic: `vifusion echo` configured for the veth
(unicast peer at the other end) makes the same counter move with its discovery messages.

usage: interface_isolation_test.py BIN_DIR SIM_DIR WORK_DIR DDS_CONFIG
DDS_CONFIG: the loopback-only configuration under test (systemd/cyclonedds.xml, the installed default).
Needs root (skips otherwise, exit 77); CI runs as root.
"""
import os
import re
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
    """Fails unless every UDP socket of vifusiond and vifusion is bound to 127.0.0.1, or to 0.0.0.0 on a
    unicast port of `domain`. Returns the number of 127.0.0.1 sockets."""
    loopback = 0
    ours = [line for line in table.splitlines() if re.search(r'users:\(\("vifusion', line)]
    if not ours:
        fail(f"ss -uapn lists no socket of vifusiond or vifusion:\n{table}")
    for line in ours:
        local = line.split()[3]
        address, port = local.rsplit(":", 1)
        if address == "127.0.0.1":
            loopback += 1
        elif address in ("0.0.0.0", "*") and int(port) in domain_unicast_ports(domain):
            continue  # Cyclone 0.10's unicast receive sockets (see the top of this file)
        else:
            fail(f"a DDS socket is bound to {local}, neither loopback nor a domain {domain} receive port: {line}")
    if loopback == 0:
        fail("no socket bound to 127.0.0.1: the transmit sockets should be bound to lo's address")
    return loopback


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
    print(f"{check_sockets(table, domain)} DDS sockets bound to 127.0.0.1, the others to 0.0.0.0 on domain "
          f"{domain}'s receive ports", flush=True)
    if code != 0:
        fail(f"vifusiond exited with {code} after SIGTERM")

    # Control: the same counter sees DDS when DDS is configured to use that interface.
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
