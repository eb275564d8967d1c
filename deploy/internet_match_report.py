#!/usr/bin/env python3
"""Figures of one deploy/internet-match.sh run, from its bot processes' and the server's JSON.

Usage: internet_match_report.py OUT_DIR BOTS PROCESSES SCHEME LINK_JSON [OUT_JSON] [LINK_ARGS]

Staleness: the age of each newest snapshot at arrival beyond the path's fastest delivery, on the
server's tick clock (throng-bots' snapshot_staleness_ms). Across processes: command->applied and
staleness p50 are the median of the processes' p50s, p99 and max the worst process's.

A stream counts as fallen behind when its staleness p99 is over LATE_TICKS ticks, or when the
ticks it received plus the ticks it counted as missed cover less than 95 % of the ticks it watched.
TCP delivers everything late rather than losing it: such a stream says "0 missed" while what the
player sees ages. Exit 1 when a bot did not join or play, 3 when every bot played but the stream
fell behind.
"""
import glob
import json
import statistics
import sys

LATE_TICKS = 4


def main():
    out_dir, want, procs, scheme, link_json = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
    out_json = sys.argv[6] if len(sys.argv) > 6 else ""
    link_args = sys.argv[7] if len(sys.argv) > 7 else ""
    runs = [json.load(open(p)) for p in sorted(glob.glob(f"{out_dir}/bots-*.json"))]
    server = json.load(open(f"{out_dir}/server.json"))
    link = json.load(open(link_json))
    per = [c for r in runs for c in r["per_client"]]
    hz = runs[0]["tick_hz"]
    joined = sum(r["joined"] for r in runs)
    lat = [r["latency_ms"] for r in runs if r["latency_ms"]["count"] > 0]
    inter = [r["snapshot_interarrival_ms"] for r in runs if r["snapshot_interarrival_ms"]["count"] > 0]
    stale = [r["snapshot_staleness_ms"] for r in runs if r["snapshot_staleness_ms"]["count"] > 0]
    received = sum(c["snapshots"]["received"] for c in per)
    gaps = sum(c["snapshots"]["gap_ticks"] for c in per)
    watched_ticks = sum(c["active_s"] * hz for c in per)
    covered = (received + gaps) / watched_ticks if watched_ticks else 0.0
    missed = gaps / (received + gaps) if received + gaps else 1.0
    per_s = statistics.mean(c["snapshots"]["received"] / c["active_s"] for c in per if c["active_s"] > 0)
    kbps = statistics.mean(c["kbit_per_s"] for c in per)
    mb = statistics.mean(c["snapshots"]["bytes"] for c in per) / 1e6
    fig = {
        "scheme": scheme,
        "link": link_args,
        "bots": want,
        "processes": procs,
        "joined": joined,
        "tick_hz": hz,
        "latency_ms": {"p50": statistics.median(l["p50"] for l in lat) if lat else None,
                       "p99": max(l["p99"] for l in lat) if lat else None,
                       "max": max(l["max"] for l in lat) if lat else None},
        "interarrival_ms": {"p99": max(i["p99"] for i in inter) if inter else None,
                            "max": max(i["max"] for i in inter) if inter else None},
        "staleness_ms": {"p50": statistics.median(x["p50"] for x in stale) if stale else None,
                         "p99": max(x["p99"] for x in stale) if stale else None,
                         "max": max(x["max"] for x in stale) if stale else None},
        "missed": missed,
        "ticks_covered": covered,
        "snapshots_per_s": per_s,
        "kbit_per_s_per_client": kbps,
        "mb_per_client": mb,
        "seconds": runs[0]["duration_s"],
        "server_clients": len(server["clients"]),
        "link_loss": {d: link[d]["loss_rate"] for d in ("up", "down")},
        "nat": link["nat"],
    }
    # Late: what the player sees is more than LATE_TICKS ticks older than the path allows, at p99.
    behind = covered < 0.95 or (fig["staleness_ms"]["p99"] or 0) > LATE_TICKS * 1000.0 / hz
    fig["fell_behind"] = behind
    l, i = fig["latency_ms"], fig["interarrival_ms"]
    fmt = lambda v: "-" if v is None else f"{v:.0f}"
    print(f"internet-match: {scheme}: {joined}/{want} joined; command->applied p50 {fmt(l['p50'])} / p99 {fmt(l['p99'])} / "
          f"max {fmt(l['max'])} ms; snapshot inter-arrival p99 {fmt(i['p99'])} / max {fmt(i['max'])} ms; "
          f"staleness p50 {fmt(fig['staleness_ms']['p50'])} / p99 {fmt(fig['staleness_ms']['p99'])} / "
          f"max {fmt(fig['staleness_ms']['max'])} ms; {100 * missed:.2f} % missed; {per_s:.1f} of {hz} snapshots/s ({100 * covered:.1f} % of ticks received or "
          f"counted missed{'; FELL BEHIND' if behind else ''}); {kbps:.0f} kbit/s, {mb:.2f} MB per client; "
          f"link loss up {100 * fig['link_loss']['up']:.2f} % down {100 * fig['link_loss']['down']:.2f} %")
    if out_json:
        with open(out_json, "w") as f:
            json.dump(fig, f, indent=2)
    played = joined == want and fig["server_clients"] == want
    played = played and all(c["snapshots"]["received"] > 0 and c["commands"]["applied"] > 0 for c in per)
    if not played:
        print("internet-match: FAILED: a bot did not join or play", file=sys.stderr)
        return 1
    if behind:
        print(f"internet-match: FAILED: the stream fell behind the match (staleness p99 over {LATE_TICKS} ticks, "
              "or ticks neither received nor counted missed)", file=sys.stderr)
        return 3
    return 0


if __name__ == "__main__":
    sys.exit(main())
