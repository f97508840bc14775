"""Issue 22 item 5 under systemd itself: vifusiond run by the shipped unit, SIGKILLed at random moments, is
restarted by systemd (Restart=on-failure, RestartSec=) and publishes again within 10 s each time, with the same
configuration, and leaves no partial file.

usage: systemd_restart_test.py BIN_DIR SIM_DIR WORK_DIR DDS_CONFIG UNIT_TEMPLATE SYSUSERS

The test unit is systemd/vifusiond.service.in generated as an install would (ExecStart= in the staged bindir)
plus one drop-in: no default dependencies (this systemd starts nothing but the service: no sysinit.target on
the build machine's file system), the test's configuration and a writable output directory. Every hardening
setting, User=, the watchdog and the restart policy are the shipped ones.

That systemd is PID 1 of its own PID, mount and UTS namespaces (`unshare`, as a container manager would start
it), with a private /run holding the units and a staged copy of the daemon, the sequence and the configuration
(ProtectHome= would hide a checkout under /root or /home). It shares the network (DDS on loopback, heard here by
`vifusion echo`) and the cgroup hierarchies, so it runs only where PID 1 is not systemd — CI's machines and
containers, where nothing else owns the hierarchies; each cgroup it made is removed afterwards. Needs root
(exit 77, skipped, otherwise or where systemd already runs the machine).
"""
import os
import random
import shutil
import signal
import subprocess
import sys
import time

from output_checks import check_directory
from service_harness import Echo, dds_domain_and_partition, fail, main, skip, start

BIN, SIM, WORK, DDS_CONFIG, UNIT_TEMPLATE, SYSUSERS = sys.argv[1:7]
KILLS = 20
PUBLISH_AGAIN_S = 10.0
FIRST_PUBLISH_S = 60.0  # a cold start: Vulkan pipelines built by lavapipe on a loaded CI machine
STAGE = "/run/vifusion-test"  # inside the namespaces' private /run
SYSTEMD = "/lib/systemd/systemd"
CGROUP_ROOT = "/sys/fs/cgroup"


def cgroup_directories():
    found = set()
    for top, dirs, _ in os.walk(CGROUP_ROOT):
        found.update(os.path.join(top, d) for d in dirs)
    return found


def remove_new_cgroups(before):
    for path in sorted(cgroup_directories() - before, key=len, reverse=True):
        try:
            os.rmdir(path)
        except OSError:
            pass


def stage_files(stage, domain, partition):
    """The daemon, sequence, DDS configuration, service configuration and units, as the namespace will see them
    under STAGE; returns the configuration's text."""
    for sub in ("bin", "out", "units/vifusiond.service.d"):
        os.makedirs(os.path.join(stage, sub))
    shutil.copy2(os.path.join(BIN, "vifusiond"), os.path.join(stage, "bin"))
    shutil.copytree(SIM, os.path.join(stage, "sim"))
    shutil.copy2(DDS_CONFIG, os.path.join(stage, "cyclonedds.xml"))
    config = (f"source: \"dataset:{STAGE}/sim\"\nout: {STAGE}/out\nmode: rgbd\nrealtime: true\nreplay_loops: 1000\n"
              f"map_file: {STAGE}/out/map.vifmap\nmap_file_required: false\nmap_save_period_s: 0.5\n"
              f"dds:\n  domain: {domain}\n  partition: {partition}\n  config: {STAGE}/cyclonedds.xml\n")
    with open(os.path.join(stage, "vifusiond.yaml"), "w") as f:
        f.write(config)
    with open(UNIT_TEMPLATE) as f:
        unit = f.read().replace("@VIFUSION_BINDIR@", f"{STAGE}/bin")
    with open(os.path.join(stage, "units", "vifusiond.service"), "w") as f:
        f.write(unit)
    with open(os.path.join(stage, "units", "vifusiond.service.d", "test.conf"), "w") as f:
        f.write("[Unit]\nDefaultDependencies=no\n[Service]\nExecStart=\n"
                f"ExecStart={STAGE}/bin/vifusiond --config {STAGE}/vifusiond.yaml\nReadWritePaths={STAGE}/out\n")
    with open(os.path.join(stage, "units", "vifusion-test.target"), "w") as f:
        f.write("[Unit]\nDescription=vifusiond under test\nDefaultDependencies=no\nWants=vifusiond.service\n")
    # The unit's Wants=network-online.target would otherwise pull in sysinit.target.
    os.makedirs(os.path.join(stage, "units", "network-online.target.d"))
    with open(os.path.join(stage, "units", "network-online.target.d", "test.conf"), "w") as f:
        f.write("[Unit]\nDefaultDependencies=no\n")
    return config


def systemctl(manager_pid, *args):
    return subprocess.run(["nsenter", f"--target={manager_pid}", "--mount", "--pid", "--", "systemctl", *args],
                          capture_output=True, text=True)


def unit_property(manager_pid, name):
    return systemctl(manager_pid, "show", "--property", name, "--value", "vifusiond.service").stdout.strip()


def wait_until_active(manager_pid, after):
    """Type=notify: active once the daemon sent READY=1 (its first frame through the whole pipeline)."""
    deadline = time.monotonic() + FIRST_PUBLISH_S
    while (state := unit_property(manager_pid, "ActiveState")) != "active":
        if time.monotonic() > deadline:
            fail(f"{after}: vifusiond.service is {state}, not active, {FIRST_PUBLISH_S:.0f} s after it published")
        time.sleep(0.2)


def wait_for_status(domain, partition, timeout_s, after):
    started = time.monotonic()
    echo = Echo(f"{BIN}/vifusion", "rt/vifusion/status", 1, timeout_s,
                ["--dds-config", DDS_CONFIG, "--domain", str(domain), "--partition", partition])
    if echo.wait(timeout_s + 5) != 0 or not echo.lines:
        fail(f"{after}: no status from the service within {timeout_s:.0f} s")
    return echo.lines[0][0] - started


def restart_case():
    if os.geteuid() != 0:
        skip("needs root: it runs systemd in namespaces of its own")
    if os.path.isdir("/run/systemd/system"):
        skip("systemd runs this machine: a second systemd would share its cgroup hierarchies")
    for tool in ("unshare", "nsenter", "systemd-sysusers"):
        if not shutil.which(tool):
            skip(f"{tool} missing")
    if not os.path.exists(SYSTEMD):
        skip(f"{SYSTEMD} missing")
    # The unit's User= and SupplementaryGroups=, as the package's postinst makes them.
    subprocess.run(["systemd-sysusers", SYSUSERS], check=True)

    shutil.rmtree(WORK, ignore_errors=True)
    stage = os.path.join(WORK, "stage")
    domain, partition = dds_domain_and_partition("systemd-restart-test")
    config = stage_files(stage, domain, partition)
    inner = os.path.join(WORK, "manager.sh")
    with open(inner, "w") as f:
        f.write(f"""set -e
mount -t tmpfs -o mode=755 tmpfs /run
mkdir -p {STAGE} /run/systemd/system
cp -a {stage}/. {STAGE}/
chown vifusion:vifusion {STAGE}/out
cp -a {STAGE}/units/. /run/systemd/system/
exec env container=vifusion-test {SYSTEMD} --system --unit=vifusion-test.target --log-target=kmsg
""")

    cgroups_before = cgroup_directories()
    # StateDirectory= and LogsDirectory= are made on the shared file system; removed afterwards if this test made them.
    service_dirs = [d for d in ("/var/lib/vifusion", "/var/log/vifusion") if not os.path.exists(d)]
    unshare = start(["unshare", "--pid", "--fork", "--kill-child=SIGKILL", "--mount", "--mount-proc", "--uts", "--", "sh", inner],
                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    manager_pid = None

    def stop_manager():
        if manager_pid:
            os.kill(manager_pid, signal.SIGKILL)  # PID 1 of the namespace: every process in it dies with it
        unshare.wait(10)
        remove_new_cgroups(cgroups_before)
        for directory in service_dirs:
            shutil.rmtree(directory, ignore_errors=True)

    try:
        for _ in range(100):
            children = open(f"/proc/{unshare.pid}/task/{unshare.pid}/children").read().split()
            if children and os.readlink(f"/proc/{children[0]}/exe").endswith("systemd"):
                manager_pid = int(children[0])
                break
            time.sleep(0.1)
        else:
            fail("systemd did not start in its namespaces")
        out = f"/proc/{manager_pid}/root{STAGE}/out"
        wait_for_status(domain, partition, FIRST_PUBLISH_S, "the first start")
        wait_until_active(manager_pid, "the first start")

        rng = random.Random(22)
        worst_s = 0.0
        for kill in range(KILLS):
            time.sleep(rng.uniform(0.0, 3.0))
            main_pid = unit_property(manager_pid, "MainPID")
            restarts = int(unit_property(manager_pid, "NRestarts"))
            result = systemctl(manager_pid, "kill", "--signal=SIGKILL", "vifusiond.service")
            if result.returncode != 0:
                fail(f"kill {kill}: systemctl kill: {result.stderr}")
            published_s = wait_for_status(domain, partition, PUBLISH_AGAIN_S, f"kill {kill} (MainPID {main_pid})")
            worst_s = max(worst_s, published_s)
            if int(unit_property(manager_pid, "NRestarts")) != restarts + 1:
                fail(f"kill {kill}: systemd restarted the unit {unit_property(manager_pid, 'NRestarts')} times in all, "
                     f"expected {restarts + 1}")
            wait_until_active(manager_pid, f"kill {kill}")
            present = check_directory(out, {"trajectory.txt", "map.ply", "map.vifmap"}, f"kill {kill}", BIN)
            # StartLimitBurst= would leave the unit failed after a few crashes in quick succession, by design: the
            # operator's reset-failed re-arms it, as the unit's comment says.
            systemctl(manager_pid, "reset-failed", "vifusiond.service")
        with open(os.path.join(f"/proc/{manager_pid}/root{STAGE}", "vifusiond.yaml")) as f:
            if f.read() != config:
                fail("the service's configuration changed across the restarts")
        print(f"vifusiond under systemd: {KILLS} SIGKILLs, each restarted by systemd and publishing again within "
              f"{worst_s:.1f} s (limit {PUBLISH_AGAIN_S:.0f} s); files left: {', '.join(present) or 'none'}, "
              f"all complete", flush=True)
    finally:
        stop_manager()


main({"restart": restart_case}, "restart")
