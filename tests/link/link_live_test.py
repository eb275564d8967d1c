#!/usr/bin/env python3
"""throng-link between two real network namespaces: the delay and loss it applies are the ones it
was asked for, and its NAT lets in only what a port-restricted cone NAT lets in.

A UDP echo runs in the server's namespace; a prober in the clients' sends numbered datagrams and
times the echoes. After the first probe the echo also sends, to the prober, from another port
(port-restricted: dropped), to the NAT's public address on another port (unmapped: dropped) and to
the prober's private address (not routed on the internet: dropped). The same run without the NAT
is the control: there the stranger from another port does arrive, so the check can fail.

Root only (ip netns); exits 77 (skipped) elsewhere.
  link_live_test.py BIN_DIR
"""
import json
import os
import shutil
import subprocess
import sys
import time

SERVER, NAT, CLIENT = "10.77.0.1", "10.77.0.100", "10.77.1.2"

ECHO = r"""
import socket, sys, select, time
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("0.0.0.0", 9000))
other = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); other.bind(("0.0.0.0", 9001))
nat, client = sys.argv[1], sys.argv[2]
deadline = time.time() + 30; told = False
while time.time() < deadline:
    if not select.select([s], [], [], 0.5)[0]: continue
    data, peer = s.recvfrom(2048)
    if data == b"quit": break
    s.sendto(data, peer)
    if not told:
        told = True
        other.sendto(b"stranger-port", peer)                    # same host, another port
        s.sendto(b"stranger-unmapped", (nat, peer[1] + 1 if peer[1] < 65535 else 1))
        s.sendto(b"stranger-private", (client, 9100))           # the prober's private endpoint
"""

PROBE = r"""
import json, socket, sys, time, select
n, gap = int(sys.argv[1]), float(sys.argv[2])
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("0.0.0.0", 9100))
server = (sys.argv[3], 9000)
sent = {}; rtts = []; strangers = []
def drain(until):
    while True:
        left = until - time.monotonic()
        if left <= 0 or not select.select([s], [], [], left)[0]: return
        data, peer = s.recvfrom(2048)
        if data.startswith(b"stranger"): strangers.append(data.decode()); continue
        i = int(data)
        if i in sent: rtts.append((time.monotonic() - sent.pop(i)) * 1000)
for i in range(n):
    sent[i] = time.monotonic(); s.sendto(str(i).encode(), server)
    drain(time.monotonic() + gap)
drain(time.monotonic() + 1.0)
s.sendto(b"quit", server)
rtts.sort()
print(json.dumps({"sent": n, "echoed": len(rtts), "strangers": strangers,
                  "rtt_p50": rtts[len(rtts) // 2] if rtts else None, "rtt_min": rtts[0] if rtts else None}))
"""


def run(bin_dir, tag, nat, probes, link_args):
    srv, cli = f"thl_t_srv_{tag}", f"thl_t_cli_{tag}"
    out_json = f"/tmp/throng-link-test-{tag}.json"
    for ns in (srv, cli):
        subprocess.run(["ip", "netns", "add", ns], check=True)
    link = None
    try:
        args = [f"{bin_dir}/throng-link", "--server-ns", srv, "--client-ns", cli, "--seed", "7", "--json", out_json]
        args += link_args + ([] if nat else ["--no-nat"])
        link = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        first = link.stdout.readline()
        if not first.startswith("throng-link: up"):
            raise SystemExit(f"throng-link did not come up: {first}{link.stdout.read()}")
        echo = subprocess.Popen(["ip", "netns", "exec", srv, sys.executable, "-c", ECHO, NAT, CLIENT])
        time.sleep(0.3)
        probe = subprocess.run(["ip", "netns", "exec", cli, sys.executable, "-c", PROBE, str(probes), "0.002", SERVER],
                               capture_output=True, text=True, timeout=60)
        echo.wait(timeout=40)
        if probe.returncode != 0:
            raise SystemExit(f"the prober failed: {probe.stderr}")
        link.terminate()
        link.communicate(timeout=10)
        return json.loads(probe.stdout), json.load(open(out_json))
    finally:
        if link and link.poll() is None:
            link.kill()
        for ns in (srv, cli):
            subprocess.run(["ip", "netns", "del", ns], stderr=subprocess.DEVNULL)


def main():
    if os.geteuid() != 0 or not shutil.which("ip"):
        print("link_live_test: needs root and iproute2; skipped")
        return 77
    bin_dir = sys.argv[1]
    failures = []

    def expect(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    tag = str(os.getpid())
    loss, delay, jitter, n = 0.05, 20.0, 2.0, 1500
    probe, link = run(bin_dir, tag + "n", True, n,
                      ["--delay-ms", str(delay), "--jitter-ms", str(jitter), "--loss", str(loss)])
    want = (1 - loss) ** 2
    sigma = (want * (1 - want) / n) ** 0.5
    got = probe["echoed"] / n
    expect(abs(got - want) <= 4 * sigma, f"round trips delivered {got:.3f}, asked {want:.3f} +- {4 * sigma:.3f}")
    for d in ("up", "down"):
        p = link[d]["packets"]
        rate = link[d]["loss_rate"]
        tol = 4 * (loss * (1 - loss) / max(p, 1)) ** 0.5
        expect(abs(rate - loss) <= tol, f"{d}: loss {rate:.4f} of {p} packets, asked {loss} +- {tol:.4f}")
        dl = link[d]["delay_ms"]
        expect(delay - jitter - 0.1 <= dl["min"] and dl["max"] <= delay + jitter + 0.2,
               f"{d}: delay {dl['min']:.1f}..{dl['max']:.1f} ms within {delay} +- {jitter}")
        expect(abs(dl["p50"] - delay) <= 1.5, f"{d}: delay p50 {dl['p50']:.1f} ms, asked {delay}")
    # The round trip as a program sees it: never shorter than both delays (how much longer is this
    # host's scheduling, reported, not asserted).
    expect(2 * (delay - jitter) <= probe["rtt_min"],
           f"round trip min {probe['rtt_min']:.1f} ms (p50 {probe['rtt_p50']:.1f} ms) for 2 x {delay} +- {jitter} ms")
    expect(probe["strangers"] == [], f"nothing unsolicited came through the NAT (got {probe['strangers']})")
    nat = link["nat"]
    expect(nat["filtered"] >= 1, f"the NAT filtered the datagram from another port ({nat['filtered']})")
    expect(nat["unmapped"] >= 2, f"the NAT dropped the unmapped and the private ones ({nat['unmapped']})")

    probe, link = run(bin_dir, tag + "c", False, 50, ["--delay-ms", "5"])
    expect("stranger-port" in probe["strangers"],
           f"control without NAT: the datagram from another port arrives ({probe['strangers']})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
