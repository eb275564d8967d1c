#!/usr/bin/env python3
"""deploy/soak.sh's report: soak.svg from soak.csv, and the verdict line (exit 0 = every target held).

Usage: soak_report.py OUT_DIR MINUTES VERIFY_OK(0|1)
"""
import csv
import glob
import json
import os
import sys


def load(out):
    with open(os.path.join(out, "soak.csv")) as f:
        rows = [r for r in csv.DictReader(f)]
    def num(r, k):
        try:
            return float(r[k])
        except (KeyError, ValueError):
            return None
    return [{k: num(r, k) for k in r} for r in rows]


def svg(rows, path):
    """Three stacked panels: RSS (MB), tick p50/p99 (ms), match log (MB), against minutes."""
    w, h, pad, gap = 900, 210, 55, 25
    panels = [("server RSS (MB)", [("rss_kb", 1e-3, "#1f77b4")]),
              ("tick over the last 10 s (ms)", [("tick_p50_ms", 1.0, "#2ca02c"), ("tick_p99_ms", 1.0, "#d62728")]),
              ("match log (MB)", [("log_bytes", 1e-6, "#9467bd")])]
    t = [r["t_s"] / 60.0 for r in rows if r["t_s"] is not None]
    tmax = max(t) if t else 1.0
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{len(panels) * (h + gap) + 20}" '
             'font-family="sans-serif" font-size="12">']
    for i, (title, series) in enumerate(panels):
        y0 = 10 + i * (h + gap)
        vals = [r[k] * s for k, s, _ in series for r in rows if r[k] is not None]
        vmax = max(vals) * 1.1 if vals and max(vals) > 0 else 1.0
        parts.append(f'<rect x="{pad}" y="{y0}" width="{w - pad - 10}" height="{h - 20}" fill="none" stroke="#999"/>')
        parts.append(f'<text x="{pad + 5}" y="{y0 + 14}">{title}</text>')
        parts.append(f'<text x="5" y="{y0 + 12}">{vmax:.3g}</text><text x="5" y="{y0 + h - 20}">0</text>')
        for k, s, color in series:
            pts = [(pad + (r["t_s"] / 60.0) / tmax * (w - pad - 10), y0 + (h - 20) * (1 - r[k] * s / vmax))
                   for r in rows if r[k] is not None and r["t_s"] is not None]
            if pts:
                parts.append('<polyline fill="none" stroke="%s" points="%s"/>' %
                             (color, " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)))
        parts.append(f'<text x="{w - 60}" y="{y0 + h - 5}">{tmax:.1f} min</text>')
    parts.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(parts))


def main():
    out, minutes, verify_ok = sys.argv[1], float(sys.argv[2]), sys.argv[3] == "1"
    rows = [r for r in load(out) if r["t_s"] is not None]
    svg(rows, os.path.join(out, "soak.svg"))
    total = minutes * 60
    # The windows for an hour; a shorter run scales them.
    base_s = 300 if minutes >= 30 else total / 12
    p99_s = 600 if minutes >= 30 else total / 6
    rss = [r for r in rows if r["rss_kb"]]
    after = [r["rss_kb"] for r in rss if r["t_s"] >= base_s]
    # Growth compared like with like: the resident memory swings by each wave's snapshot state, so
    # the first and last samples after the baseline taken with the same number of clients present
    # (the median of three at each end, as a sample's client count is read from a progress line
    # up to 10 s old); the largest such growth over the client counts seen at both ends. Without
    # three samples at both ends for any count, the first and last samples.
    by_clients = {}
    for r in rss:
        if r["t_s"] >= base_s and r.get("clients") is not None:
            by_clients.setdefault(r["clients"], []).append(r["rss_kb"])
    med3 = lambda v: sorted(v)[len(v) // 2]
    like = [med3(v[-3:]) / med3(v[:3]) - 1.0 for v in by_clients.values() if len(v) >= 6]
    if like:
        rss_growth = max(like)
    else:
        rss_growth = (after[-1] / after[0] - 1.0) if len(after) >= 2 else float("nan")
    first = [r["tick_p99_ms"] for r in rows if r["tick_p99_ms"] is not None and r["t_s"] <= p99_s]
    last = [r["tick_p99_ms"] for r in rows if r["tick_p99_ms"] is not None and r["t_s"] >= rows[-1]["t_s"] - p99_s]
    p99_first = sum(first) / len(first) if first else float("nan")
    p99_last = sum(last) / len(last) if last else float("nan")
    p99_change = p99_last / p99_first - 1.0 if first and last and p99_first > 0 else float("nan")
    gaps, bots = 0, 0
    for path in glob.glob(os.path.join(out, "bots-*.json")):
        try:
            with open(path) as f:
                j = json.load(f)
            gaps += int(j.get("snapshot_gap_ticks", 0))
            bots += int(j.get("joined", 0))
        except (OSError, ValueError):
            gaps += 1  # a wave that wrote no report cannot vouch for its snapshots
    checks = [("rss", rss_growth < 0.01), ("p99", p99_change <= 0.10), ("gaps", gaps == 0), ("log", verify_ok)]
    ok = all(c for _, c in checks)
    print(f"soak verdict: {'PASS' if ok else 'FAIL'} ({minutes:g} min, {len(rows)} samples, {bots} bot sessions) | "
          f"RSS after {base_s / 60:.3g} min {rss_growth * 100:+.2f}% at equal clients (target < 1%) | tick p99 first/last "
          f"{p99_s / 60:.3g} min {p99_first:.2f}/{p99_last:.2f} ms ({p99_change * 100:+.1f}%, target at most +10%) | "
          f"snapshot gaps {gaps} (target 0) | log {'verifies' if verify_ok else 'DOES NOT VERIFY'} | "
          f"{os.path.join(out, 'soak.csv')}, soak.svg")
    # The RSS by clients present (medians of the first and last three samples), and the largest
    # sample after the baseline against the first: what the verdict's figure is made of.
    parts = [f"{c:g} clients {med3(v[:3]) / 1e3:.1f} -> {med3(v[-3:]) / 1e3:.1f} MB "
             f"({(med3(v[-3:]) / med3(v[:3]) - 1.0) * 100:+.2f}%, {len(v)} samples)"
             for c, v in sorted(by_clients.items()) if len(v) >= 6]
    if parts:
        print("soak: RSS after " + f"{base_s / 60:.3g} min by clients present: " + "; ".join(parts) +
              f" | largest sample {max(after) / 1e3:.1f} MB against {after[0] / 1e3:.1f} MB at the baseline")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
