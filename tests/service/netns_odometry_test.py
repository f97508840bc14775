#!/usr/bin/env python3
"""The odometry reaches a DDS consumer on another machine: vifusiond runs in one network namespace,
`vifusion echo rt/vifusion/odometry` in a second one, and the only link between them is a veth pair.
Each side's Cyclone configuration names only its own veth end, has multicast off and the other end's
address as its unicast peer — the set-up of a robot on a network without multicast.

usage: netns_odometry_test.py BIN_DIR SIM_DIR WORK_DIR
Needs root (skips otherwise, exit 77); CI runs as root.
"""
import os
import sys

from netns import VethPair, require_root_and_ip, write_unicast_config
from service_harness import Echo, check_odometry, dds_domain_and_partition, fail, main, on_exit, start, stop

BIN, SIM, WORK = sys.argv[1:4]
MESSAGES = 10


def odometry_across_namespaces():
    require_root_and_ip()
    net = VethPair()
    on_exit(net.delete)
    net.create()
    work = f"{WORK}/netns-{os.getpid()}"
    os.makedirs(work, exist_ok=True)
    daemon_config = write_unicast_config(f"{work}/daemon.xml", net.if_a, net.addr_b)
    reader_config = write_unicast_config(f"{work}/reader.xml", net.if_b, net.addr_a)
    domain, partition = dds_domain_and_partition("netns-test")

    odometry = Echo(f"{BIN}/vifusion", "rt/vifusion/odometry", MESSAGES, 40,
                    ["--dds-config", reader_config, "--domain", str(domain), "--partition", partition],
                    prefix=net.exec(net.ns_b))
    service = start([*net.exec(net.ns_a), f"{BIN}/vifusiond", "--source", f"dataset:{SIM}", "--out", f"{work}/out",
                     "--realtime", "true", "--dds.config", daemon_config, "--dds.domain", str(domain),
                     "--dds.partition", partition])
    if odometry.wait(45) != 0:
        fail(f"the reader in {net.ns_b} received {len(odometry.lines)} of {MESSAGES} odometry messages "
             f"from vifusiond in {net.ns_a}")
    moved, stamps = check_odometry(odometry.lines)
    code = stop(service)
    sent, received = net.counters(net.ns_a, net.if_a), net.counters(net.ns_b, net.if_b)
    print(f"{len(stamps)} odometry messages crossed the veth pair; the camera moved {moved * 1000:.1f} mm over "
          f"{stamps[-1] - stamps[0]:.3f} s of data; {net.if_a} sent {sent['tx']['packets']} packets "
          f"({sent['tx']['bytes']} bytes), {net.if_b} received {received['rx']['packets']}", flush=True)
    if code != 0:
        fail(f"vifusiond exited with {code} after SIGTERM")


main({"odometry": odometry_across_namespaces}, "odometry")
