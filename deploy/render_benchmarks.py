#!/usr/bin/env python3
"""Renders docs/benchmarks.md and the engine rows of the README's figures table from the raw
results that deploy/make-benchmarks-doc.sh keeps in server/bench/results/:

  crush-sweep.json        throng-bench sweep (K sweep and N sweep on crush, one_cell)
  threads.json            deploy/measure-threads.sh (JSON_OUT)
  worst-tick.json         deploy/measure-worst-tick.sh (JSON_OUT)
  contact-validation.txt  throng-bench validate-contacts
  machine.json            where and when they were measured
  internet/*.json         deploy/measure-internet.sh: players across an emulated internet path
                          (optional: the section is left out without them)

Every measured figure in the output comes from those files, so the document cannot drift from
them; the prose here names only the scenes' fixed settings. The README keeps its one table: rows whose first cell is a key
below are replaced, the others (server, log, security figures) are left as they are.

  render_benchmarks.py RESULTS_DIR BENCHMARKS_MD README_MD
"""
import json
import os
import re
import sys

# The engine's targets (docs/design/solver.md, "Iterations") and the worst-tick and two-thread
# targets of the issue on the worst tick, checked on every render.
TARGET_20K_MS = 2.0
TARGET_MAX_R = 0.20
TARGET_P99_R = 0.05
TARGET_100K_MS = 12.0
TARGET_FLAT = 1.5
TARGET_ONE_CELL = 5.0
TARGET_WORST_MAX_R = 0.25
TARGET_WORST_P99_R = 0.05
TARGET_THREADS_100K = 1.6


def fail(msg):
    sys.exit("render_benchmarks: " + msg)


def load_json(results, name):
    path = os.path.join(results, name)
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        fail(f"{path} is missing: run deploy/make-benchmarks-doc.sh without --render first")
    except json.JSONDecodeError as e:
        fail(f"{path} is not valid JSON ({e})")


def ms(us):
    return f"{us / 1000:.2f}"


def n_fmt(n):
    return f"{n:,}"


def met(ok):
    return "met" if ok else "**not met**"


def sweep_section(sweep):
    k_runs, n_runs, one = sweep["k_sweep"], sweep["n_sweep"], sweep["one_cell"]
    default_k = sweep["default_iterations"]
    out = []
    n_k = k_runs[0]["agents"] if k_runs else 0
    out.append(f"## Speed against error: iterations K (crush, N = {n_fmt(n_k)}, {sweep['ticks']} ticks at 60 Hz)\n")
    out.append("![speed vs error](../server/bench/results/crush-sweep.svg)\n")
    out.append("| K | median µs/tick | p95 µs | max pen / r | p99 pen / r | pairs > 1% | worst max / r | worst p99 / r |")
    out.append("|---|---|---|---|---|---|---|---|")
    for r in k_runs:
        k = f"{r['iterations']} (default)" if r["iterations"] == default_k else str(r["iterations"])
        res, rot = r["residual"], r["residual_over_time"]
        out.append(f"| {k} | {r['tick_us']['median']:,.0f} | {r['tick_us']['p95']:,.0f} | {res['max_pen_over_radius']:.3f} | "
                   f"{res['p99_pen_over_radius']:.3f} | {res['pairs_over_1pct']:,} | {rot['worst_max_pen_over_radius']:.3f} | "
                   f"{rot['worst_p99_pen_over_radius']:.3f} |")
    frm = k_runs[0]["residual_over_time"]["from_tick"] if k_runs else 61
    out.append(f"\nmax / p99: after the last tick; worst: the largest over ticks {frm}–{sweep['ticks']}. Why K = {default_k} "
               "and why fewer sweeps are not cheaper: [`design/solver.md`](design/solver.md#iterations-k--8-by-default).\n")

    out.append(f"## Scaling in N (crush, K = {default_k})\n")
    out.append("| N | median µs/tick | p95 µs | µs per agent | max pen / r | p99 pen / r | worst max / r | worst p99 / r |")
    out.append("|---|---|---|---|---|---|---|---|")
    for r in n_runs:
        res, rot = r["residual"], r["residual_over_time"]
        out.append(f"| {n_fmt(r['agents'])} | {r['tick_us']['median']:,.0f} | {r['tick_us']['p95']:,.0f} | {r['us_per_agent']:.3f} | "
                   f"{res['max_pen_over_radius']:.3f} | {res['p99_pen_over_radius']:.3f} | "
                   f"{rot['worst_max_pen_over_radius']:.3f} | {rot['worst_p99_pen_over_radius']:.3f} |")
    run = one["run"]
    out.append(f"\n**one_cell** ({n_fmt(run['agents'])} bodies started at one point): {one['one_cell_us_per_agent']:.3f} µs per "
               f"agent, {one['cost_ratio']:.2f}× the uniform crowd's cost per agent; residual max "
               f"{run['residual']['max_pen_over_radius']:.3f} r after the last tick.\n")
    return out


def threads_section(threads):
    out = ["## Threads\n",
           f"`deploy/measure-threads.sh {threads['reps']}`: one and two solver threads alternately, "
           f"{threads['reps']} runs each, {threads['ticks']} ticks, medians of the runs' medians.\n"]
    out.append("| scene | N | 1 thread: median / p95 µs (solve) | 2 threads: median / p95 µs (solve) | speed-up (median) | same hash |")
    out.append("|---|---|---|---|---|---|")
    for r in threads["rows"]:
        one, two = r["by_threads"]["1"], r["by_threads"]["2"]
        out.append(f"| {r['scene']} | {n_fmt(r['agents'])} | {one['median_us']:,.0f} / {one['p95_us']:,.0f} ({one['solve_us']:,.0f}) | "
                   f"{two['median_us']:,.0f} / {two['p95_us']:,.0f} ({two['solve_us']:,.0f}) | "
                   f"{one['median_us'] / two['median_us']:.2f}× | {'yes' if r['same_hash'] else 'NO'} |")
    out.append("\n`--threads N` on the bench, `--solver-threads N` on the server; the tests also compare 1, 2 and 4 threads "
               "every tick. Why small crowds gain little: [`design/solver.md`](design/solver.md#threads-the-same-bits-on-any-number).\n")
    return out


def worst_section(worst):
    out = ["## The worst tick\n",
           "`deploy/measure-worst-tick.sh 5000 20000`, K = 8; the independent metric after every tick from tick 61 to 300. `crush_post` and `crush_pillars` are "
           "`server/engine/data/scenes/crush_post.json` and `crush_pillars.json` (the crush with a fixed post of radius 0.5 m at "
           "its goal, and with eight such pillars on a 3 m ring around it, the same at every N: only the crowd scales); `mixed` is the mixed crowd with the built-in weights; each with "
           "`blocked_motion_carry` at its default and at 0.\n",
           "| scene | N | carry | worst max / r | worst p99 / r | ticks over 0.5 r | median µs | p95 µs |",
           "|---|---|---|---|---|---|---|---|"]
    for r in worst["rows"]:
        rot, t = r["residual_over_time"], r["tick_us"]
        out.append(f"| {r['scene']} | {n_fmt(r['agents'])} | {r['carry']} | {rot['worst_max_pen_over_radius']:.3f} | "
                   f"{rot['worst_p99_pen_over_radius']:.3f} | {rot['ticks_over_0_5_r']} | {t['median']:,.0f} | {t['p95']:,.0f} |")
    out.append("")
    return out


# The internet path's targets (issue 44): UDP through the NAT at 2 % loss against the same path
# without loss, at 100 and 200 ms round trip.
TARGET_LOSSY_P99_RATIO = 1.25
TARGET_INTERARRIVAL_TICKS = 3
TARGET_MISSED_OVER_LOSS = 0.005


def internet_section(results):
    folder = os.path.join(results, "internet")
    if not os.path.isdir(folder):
        return []
    cells = {}
    for name in sorted(os.listdir(folder)):
        if name.endswith(".json"):
            cells[name[:-5]] = json.load(open(os.path.join(folder, name)))
    if not cells:
        return []
    order = [f"rtt{r}-loss{l}" for r in (40, 100, 200) for l in ("0", "0.01", "0.02", "0.03")] + ["rtt100-burst"]
    out = ["## Players across an emulated internet path\n"]
    out.append("`deploy/measure-internet.sh`: the server in one network namespace, 20 bots in 4 `throng-bots` processes "
               "in another behind a home NAT (port-restricted cone), joined by `throng-link` with ±5 ms jitter and the "
               "loss given, in both directions; the default battle scaled to 1,000 NPCs, 30 Hz. Burst: Gilbert–Elliott, "
               "1 % chance per packet to enter a burst, mean burst 4 packets. Staleness: each newest snapshot's age at "
               "arrival beyond the path's fastest delivery, on the server's tick clock; **fell behind**: its p99 over "
               "4 ticks (what the player sees is that much older than the path allows) while the bots count the "
               "ticks as received. Command→applied and staleness p50: the median of the processes'; p99 and max: the "
               "worst process's.\n")
    out.append("| path | round trip | loss | joined | command→applied p50 / p99 / max ms | snapshot inter-arrival p99 / max ms "
               "| staleness p50 / p99 / max ms | missed | snapshots/s | kbit/s per client |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    f = lambda v: "–" if v is None else f"{v:,.0f}"
    for scheme in ("udp", "tcp"):
        for key in order:
            c = cells.get(f"{scheme}-{key}")
            if c is None:
                continue
            rtt = key.split("-")[0][3:]
            loss = "burst" if key.endswith("burst") else f"{float(key.split('loss')[1]) * 100:g} %"
            l, i, st = c["latency_ms"], c["interarrival_ms"], c["staleness_ms"]
            path = "UDP (NAT)" if scheme == "udp" else "TCP (NAT)"
            behind = " **fell behind**" if c["fell_behind"] else ""  # internet_match_report.py's verdict
            out.append(f"| {path} | {rtt} ms | {loss} | {c['joined']}/{c['bots']} | {f(l['p50'])} / {f(l['p99'])} / {f(l['max'])} "
                       f"| {f(i['p99'])} / {f(i['max'])} | {f(st['p50'])} / {f(st['p99'])} / {f(st['max'])} "
                       f"| {100 * c['missed']:.2f} %{behind} | {c['snapshots_per_s']:.1f} of {c['tick_hz']} "
                       f"| {c['kbit_per_s_per_client']:.0f} |")
    out.append("")
    rows = []
    for rtt in (100, 200):
        clean, lossy = cells.get(f"udp-rtt{rtt}-loss0"), cells.get(f"udp-rtt{rtt}-loss0.02")
        if not clean or not lossy:
            continue
        ratio = lossy["latency_ms"]["p99"] / clean["latency_ms"]["p99"]
        tick_ms = 1000.0 / lossy["tick_hz"]
        ia = lossy["interarrival_ms"]["p99"] / tick_ms
        missed_ok = lossy["missed"] <= 0.02 + TARGET_MISSED_OVER_LOSS
        rows.append(f"| UDP through the NAT, {rtt} ms, 2 % loss | command→applied p99 {ratio:.2f}× the lossless path's "
                    f"(≤ {TARGET_LOSSY_P99_RATIO}) {met(ratio <= TARGET_LOSSY_P99_RATIO)}; inter-arrival p99 {ia:.1f} ticks "
                    f"(≤ {TARGET_INTERARRIVAL_TICKS}) {met(ia <= TARGET_INTERARRIVAL_TICKS)}; missed {100 * lossy['missed']:.2f} % "
                    f"(≤ 2.5 %) {met(missed_ok)} |")
    if rows:
        out.append("| target | measured |")
        out.append("|---|---|")
        out += rows
        out.append("")
    return out


def contact_section(text):
    # The "all" rows of sections [1] (closed form vs long double) and [2] (fcl::distance).
    alls = [[t for t in l.split() if t != "|"] for l in text.splitlines() if l.startswith("all ")]
    if len(alls) < 2:
        fail("contact-validation.txt has no 'all' rows: is it throng-bench validate-contacts output?")
    closed, fcl = alls[0], alls[1]
    pairs = closed[1]
    # [1] ends with its ">bound" and "bad" counts, [2] with fcl::distance's failures.
    failures = int(closed[-2]) + int(closed[-1])
    out = ["## Contact validation\n",
           f"`throng-bench validate-contacts --pairs 100000`: the closed-form capsule–capsule contact (double) against an independent long-double reference over {int(pairs):,} "
           f"random pairs in 8 families (generic, parallel, near-parallel, crossing, spheres, touching, deep, 10 km from the "
           f"origin): distance error max {closed[3]} m, p99 {closed[4]} m; normal error max {closed[7]} rad, p99 {closed[8]} rad; "
           f"{failures} pairs beyond the bound or malformed. "
           f"`fcl::distance` on the separated pairs: max {fcl[2]} m, p99 {fcl[3]} m, {int(fcl[-1])} failures. FCL's penetration queries and the full "
           "tables: [`server/bench/results/contact-validation.txt`](../server/bench/results/contact-validation.txt); what this "
           "decided: [`design/solver.md`](design/solver.md#contacts-closed-forms-not-fcl-for-capsules).\n"]
    return out


def targets(sweep, threads, worst):
    default_k = sweep["default_iterations"]
    by_n = {r["agents"]: r for r in sweep["n_sweep"]}
    lines = ["## Against the targets\n"]
    r20 = by_n.get(20000)
    if r20:
        ok = (r20["tick_us"]["median"] / 1000 <= TARGET_20K_MS and r20["residual"]["max_pen_over_radius"] <= TARGET_MAX_R
              and r20["residual"]["p99_pen_over_radius"] <= TARGET_P99_R)
        lines.append(f"- N = 20,000 at ≤ {TARGET_20K_MS} ms with max ≤ {TARGET_MAX_R:.2f} r and p99 ≤ {TARGET_P99_R:.2f} r (K = {default_k}): "
                     f"{ms(r20['tick_us']['median'])} ms, max {r20['residual']['max_pen_over_radius']:.3f}, "
                     f"p99 {r20['residual']['p99_pen_over_radius']:.3f} — {met(ok)}.")
    r100 = by_n.get(100000)
    if r100:
        lines.append(f"- N = 100,000 at ≤ {TARGET_100K_MS:.0f} ms: {ms(r100['tick_us']['median'])} ms — "
                     f"{met(r100['tick_us']['median'] / 1000 <= TARGET_100K_MS)}.")
    costs = [r["us_per_agent"] for r in sweep["n_sweep"]]
    if costs:
        flat = max(costs) / min(costs)
        lines.append(f"- Cost per agent flat in N (≤ {TARGET_FLAT}×): {min(costs):.3f}–{max(costs):.3f} µs, {flat:.2f}× — "
                     f"{met(flat <= TARGET_FLAT)}.")
    ratio = sweep["one_cell"]["cost_ratio"]
    lines.append(f"- one_cell ≤ {TARGET_ONE_CELL:.0f}× the uniform cost per agent: {ratio:.2f}× — {met(ratio <= TARGET_ONE_CELL)}.")
    nans = sum(r.get("nan_count", 0) for r in sweep["k_sweep"] + sweep["n_sweep"] + [sweep["one_cell"]["run"]])
    lines.append(f"- No NaN: {nans} in the sweep — {met(nans == 0)}. No allocation in a tick after warm-up: "
                 "checked by `throng_alloc_tests`, not measured here.")
    t100 = next((r for r in threads["rows"] if r["scene"] == "crush" and r["agents"] == 100000), None)
    if t100:
        up = t100["by_threads"]["1"]["median_us"] / t100["by_threads"]["2"]["median_us"]
        lines.append(f"- Two threads, crush 100,000, ≥ {TARGET_THREADS_100K}× one thread with the same hash: {up:.2f}×, "
                     f"{'same hash' if t100['same_hash'] else 'hash DIFFERS'} — {met(up >= TARGET_THREADS_100K and t100['same_hash'])}.")
    rows = worst["rows"]
    inside = [r for r in rows if r["residual_over_time"]["worst_max_pen_over_radius"] <= TARGET_WORST_MAX_R
              and r["residual_over_time"]["worst_p99_pen_over_radius"] <= TARGET_WORST_P99_R]
    outside = sorted({f"{r['scene']} {n_fmt(r['agents'])} carry {r['carry']}" for r in rows if r not in inside})
    lines.append(f"- Every tick after tick 60 within max ≤ {TARGET_WORST_MAX_R} r and p99 ≤ {TARGET_WORST_P99_R} r: "
                 f"{len(inside)} of {len(rows)} runs — {met(len(inside) == len(rows))}"
                 + (f" (outside: {', '.join(outside)})." if outside else "."))
    lines.append("")
    return lines


def readme_rows(sweep, threads, worst):
    by_n = {r["agents"]: r for r in sweep["n_sweep"]}
    rows = {}
    r20, r100 = by_n.get(20000), by_n.get(100000)
    if r20:
        rows["crush 20,000 bodies, K = 8"] = (
            f"{ms(r20['tick_us']['median'])} ms per tick; residual max {r20['residual']['max_pen_over_radius']:.3f} r, "
            f"p99 {r20['residual']['p99_pen_over_radius']:.3f} r", "`throng-bench sweep`")
    if r100:
        rows["crush 100,000 bodies, K = 8"] = (f"{ms(r100['tick_us']['median'])} ms per tick", "`throng-bench sweep`")
    t100 = next((r for r in threads["rows"] if r["scene"] == "crush" and r["agents"] == 100000), None)
    if t100:
        up = t100["by_threads"]["1"]["median_us"] / t100["by_threads"]["2"]["median_us"]
        rows["crush 100,000 bodies, two solver threads"] = (
            f"{up:.2f}× one thread's speed, {'the same' if t100['same_hash'] else 'a DIFFERENT'} state hash", "`deploy/measure-threads.sh`")
    costs = [r["us_per_agent"] for r in sweep["n_sweep"]]
    if costs:
        rows["cost per body, 1k to 100k"] = (
            f"{min(costs):.3f}–{max(costs):.3f} µs (flat within {max(costs) / min(costs):.1f}×)", "`throng-bench sweep`")

    def worst_of(scene, n, carry):
        return next((r["residual_over_time"] for r in worst["rows"] if r["scene"] == scene and r["agents"] == n and r["carry"] == carry), None)

    fam = [worst_of(s, 5000, "0") for s in ("crush", "crush_post", "crush_pillars")]
    if all(fam):
        rows["worst tick (ticks 61–300), 5,000 bodies, carry 0: crush / post / pillars"] = (
            "max " + " r / ".join(f"{w['worst_max_pen_over_radius']:.2f}" for w in fam) +
            f" r; p99 ≤ {max(w['worst_p99_pen_over_radius'] for w in fam):.3f} r", "`deploy/measure-worst-tick.sh`")
    mixed = [worst_of("mixed", 5000, c) for c in ("default", "0")]
    if all(mixed):
        rows["worst tick, `mixed`, 5,000 bodies, carry default / 0"] = (
            f"max {mixed[0]['worst_max_pen_over_radius']:.2f} r / {mixed[1]['worst_max_pen_over_radius']:.2f} r; "
            f"p99 {mixed[0]['worst_p99_pen_over_radius']:.2f} r / {mixed[1]['worst_p99_pen_over_radius']:.2f} r", "`deploy/measure-worst-tick.sh`")
    return rows


def updated_readme(path, rows):
    text = open(path).read()
    for key, (figure, command) in rows.items():
        pattern = re.compile(r"^\| " + re.escape(key) + r" \|.*$", re.M)
        if not pattern.search(text):
            fail(f"{path} has no figures row '| {key} |': add it to the figures table under 'Benchmark'")
        text = pattern.sub(lambda _: f"| {key} | {figure} | {command} |", text)
    return text


def main():
    if len(sys.argv) != 4:
        fail("usage: render_benchmarks.py RESULTS_DIR BENCHMARKS_MD README_MD")
    results, doc_path, readme_path = sys.argv[1:]
    machine = load_json(results, "machine.json")
    sweep = load_json(results, "crush-sweep.json")
    threads = load_json(results, "threads.json")
    worst = load_json(results, "worst-tick.json")
    try:
        contacts = open(os.path.join(results, "contact-validation.txt")).read()
    except FileNotFoundError:
        fail(f"{results}/contact-validation.txt is missing")

    head = f"""# Benchmarks: current figures

Generated by `bash deploy/make-benchmarks-doc.sh` from the raw results in
[`server/bench/results/`](../server/bench/results/) (measured {machine['date']} at commit {machine['commit']}
on {machine['cpu']}, {machine['cores']} cores): do not edit it by hand. Release build, one solver thread
unless a table says otherwise. Timings are wall-clock medians of `World::step()` alone; a shared
machine's speed drifts within the hour, so compare rows of one table, not across tables.
Residuals are measured by an independent grid over all pairs (exact 3D upright-capsule distance),
not by the solver, after the last tick and in every tick from tick 61 (the worst tick).

**Scenes** (`throng-bench --list-scenes`): `crush` (N agents of radius 0.35 m in a disk of radius
0.5·√N m, all seeking the centre at 1.5 m/s, 60 Hz, 300 ticks), `street` (two armies meeting in a
walled street), `obstacles` (a crowd pressing on fixed boxes, cylinders and soft bushes), `mixed`
(foot, mounts, giants, heavy and light), `one_cell` (everyone at one point), `battle` (the
default: two factions, walls).

**Output** (`throng-bench --scene S --json`): `agents`, `ticks`, `iterations`, `tick_us`
{{`median`,`p95`,`max`}}, `tick_cpu_us` (the same step timed with the thread's CPU clock),
`residual` {{`max_pen_over_radius`, `p99_pen_over_radius`, `pairs_over_1pct`}},
`residual_over_time` {{`worst_max_pen_over_radius`, `worst_max_tick`, `worst_p99_pen_over_radius`,
`ticks_over_0_5_r`}} (from `--residual-from`, default 61), `static_pen_max_over_radius`,
`nan_count`, `state_hash`, per-phase medians and the solver's own figures (candidate pairs,
iterations used, the share of band sweeps left out as calm, ticks that kept the pair list, began
the next list's search or searched twice). `--trace FILE` writes one CSV line per tick; `--carry X` overrides
`blocked_motion_carry`.
"""
    out = [head]
    out += sweep_section(sweep)
    out += threads_section(threads)
    out += worst_section(worst)
    out += targets(sweep, threads, worst)
    out += contact_section(contacts)
    out += internet_section(results)
    out.append("""## Figures measured by other scripts

These measure the server, the network and the match log rather than the engine, take minutes to
an hour each, and keep their figures beside the decisions they informed:

| what | command | figures |
|---|---|---|
| server capacity, tick and latency with bots | `deploy/measure-server.sh` | [`client_sim/README.md`](../client_sim/README.md#measured-figures), [`design/snapshots.md`](design/snapshots.md) |
| DDS Security's cost | `deploy/measure-security.sh` | [`design/security.md`](design/security.md) |
| players over TCP across network namespaces | `deploy/netns-match.sh 20 10` | [`hosting.md`](hosting.md) |
| match log size, verify and seek speed | `deploy/measure-log.sh 600`, `THRONG_MEASURE_BODIES=5000 THRONG_MEASURE_TICKS=9000 throng_matchlog_tests --gtest_also_run_disabled_tests --gtest_filter='Measure*'` | [`design/match-log.md`](design/match-log.md) |
| the viewer's contact overlay | `throng_match_tests --gtest_also_run_disabled_tests --gtest_filter='MeasureContacts*'` | [`protocol/README.md`](../protocol/README.md#contact-pairs-a-debug-overlay-opt-in) |
| a one-hour soak | `deploy/soak.sh 60` | [`design/memory.md`](design/memory.md#the-soak-step-by-step) |
""")
    rows = readme_rows(sweep, threads, worst)
    if len(rows) != 6:
        fail(f"the results give {len(rows)} of the README's 6 engine rows: a run is missing from {results}")
    readme = updated_readme(readme_path, rows)  # checks every row before either file is written
    with open(doc_path, "w") as f:
        f.write("\n".join(out).rstrip() + "\n")
    with open(readme_path, "w") as f:
        f.write(readme)


if __name__ == "__main__":
    main()
