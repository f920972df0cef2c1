#!/usr/bin/env python3
"""Markdown tables of docs/performance.md from the JSON of one `humandyn bench` run.

usage: python3 docs/performance/make_tables.py docs/performance/bench.json
"""
import json
import math
import sys


def num(v, fmt="%.3g"):
    return "diverged" if v is None or (isinstance(v, float) and math.isinf(v)) else fmt % v


def main():
    doc = json.load(open(sys.argv[1]))
    m = doc["machine"]
    print("Machine: %s; compiler GCC %s; flags `%s`; -march=native %s.\n" %
          (m["cpu"], m["compiler"], m["flags"].strip(), m["march_native"]))

    print("### 1 kHz loop\n")
    print("| work per tick | K | ticks | p50 (µs) | p99 (µs) | p99.9 (µs) | max (µs) | compute mean (µs) | share of period | misses (late / overrun) | max wake-up (µs) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in doc["loop"]["runs"]:
        print("| %s | %d | %d | %.0f | %.0f | %.0f | %.0f | %.0f | %.1f %% | %d (%d / %d) | %.0f |" %
              (r["work"], r["characters"], r["ticks"], r["p50_us"], r["p99_us"], r["p999_us"], r["max_us"],
               r["compute_mean_us"], 100 * r["share"], r["misses"], r["misses_late"], r["misses_overrun"],
               r["max_wakeup_us"]))
    print()
    for f in doc["loop"]["largest_k_with_half_period_free"]:
        print("- largest K with 50 %% headroom, %s: **%d**" % (f["work"], f["characters"]))
    print()

    print("### Error against run time\n")
    print("| variant | states | ns / call | max abs error | RMS abs error | max rel error | unit |")
    print("|---|---|---:|---:|---:|---:|---|")
    for v in doc["variants"]:
        print("| %s | %s | %.0f | %s | %s | %s | %s |" %
              (v["name"], v["states"], v["ns_per_call"], num(v["max_abs_error"]), num(v["rms_abs_error"]),
               num(v["max_rel_error"]), v["unit"]))
    print()

    print("### Work-precision\n")
    print("| scenario | integrator | h (s) | ms per simulated s | end angle error (rad) | end velocity error (rad/s) |")
    print("|---|---|---:|---:|---:|---:|")
    for p in doc.get("work_precision", []):
        ok = p["ok"]
        print("| %s | %s | %.3g | %s | %s | %s |" %
              (p["scenario"], p["integrator"], p["h"], ("%.3g" % p["ms_per_sim_second"]) if ok else "—",
               num(p["q_error"]) if ok else "diverged", num(p["qd_error"]) if ok else "diverged"))
    print()

    print("### Ratios\n")
    for r in doc["ratios"]:
        print("- %s: **%.2f×**" % (r["ratio"], r["value"]))


if __name__ == "__main__":
    main()
