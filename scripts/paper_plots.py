#!/usr/bin/env python3
"""Figures and tables for docs/paper-reproduction.md, from the files scripts/reproduce-paper.sh
leaves in a folder (default docs/figures):

  sweep.csv, parsimony.csv, robustness.csv   written by bench/paper_repro
  bench_pairs.json, bench_cgal.json          Google Benchmark JSON (optional)
  run-info.txt                               machine, date, load (optional)

Writes into the same folder:

  sweep_error.png        Figure 11 (left): relative error against alpha
  sweep_time.png         Figure 11 (right): time per call against alpha
  robustness_error.png   worst error and failures against the perturbation size
  tables.md              the markdown tables quoted in docs/paper-reproduction.md

Usage: paper_plots.py [FOLDER]. Needs matplotlib (Debian: python3-matplotlib).
"""
import csv
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FOLDER = sys.argv[1] if len(sys.argv) > 1 else "docs/figures"
BOUNDARY = 2 * math.pi / 3
FLOOR = 1e-18  # zero errors are drawn here (log scale)

COLORS = {"tetia": "#1f77b4", "tetia_full": "#17becf", "clip": "#ff7f0e", "pang": "#2ca02c",
          "cgal": "#9467bd"}
LABELS = {"tetia": "tetia (intersection_volume)", "tetia_full": "tetia (intersect, full polyhedron)",
          "clip": "Sutherland-Hodgman (clip_volume)", "pang": "PANG-style (pang_volume)"}


def path(name):
    return os.path.join(FOLDER, name)


def read_csv(name):
    with open(path(name), newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def fmt(x, digits=2):
    if x == 0:
        return "0"
    if not math.isfinite(x):
        return str(x)
    return f"{x:.{digits}e}".replace("e-0", "e-").replace("e+0", "e+")


def median(xs):
    s = sorted(xs)
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def pi_ticks(ax):
    ticks = [k * math.pi / 6 for k in range(7)]
    names = ["0", "π/6", "π/3", "π/2", "2π/3", "5π/6", "π"]
    ax.set_xticks(ticks)
    ax.set_xticklabels(names)
    ax.set_xlim(0, math.pi)


def mark_regimes(ax, y_text):
    ax.axvline(BOUNDARY, color="0.3", lw=1, ls=":")
    ax.text(BOUNDARY / 2, y_text, "regime 1: cos(α/2) > 1/2", ha="center", va="top", fontsize=8,
            color="0.3")
    ax.text((BOUNDARY + math.pi) / 2, y_text, "regime 2", ha="center", va="top", fontsize=8,
            color="0.3")


# --- Section 5.2 ---------------------------------------------------------------------------


def sweep(out):
    rows = read_csv("sweep.csv")
    alpha = [float(r["alpha"]) for r in rows]
    order = sorted(range(len(rows)), key=lambda i: alpha[i])
    a = [alpha[i] for i in order]

    def col(name):
        return [float(rows[i][name]) for i in order]

    # Error (tetia_full has the same volume bit for bit; paper_repro checks and prints it).
    fig, ax = plt.subplots(figsize=(8, 4.6))
    styles = {("pang", "uv"): ("^", 2.2), ("pang", "vu"): ("v", 2.2), ("clip", "uv"): ("s", 1.8),
              ("clip", "vu"): ("D", 1.6), ("tetia", "uv"): ("o", 2.0)}
    for (m, role), (marker, ms) in styles.items():
        y = [max(v, FLOOR) for v in col(f"err_{m}_{role}")]
        label = LABELS[m] + (" (U,V) = (V,U)" if m == "tetia" else f" ({'U,V' if role == 'uv' else 'V,U'})")
        face = COLORS[m] if role == "uv" else "none"
        ax.plot(a, y, marker, ms=ms, mec=COLORS[m], mfc=face, mew=0.6, alpha=0.8, ls="none", label=label)
    ax.set_yscale("log")
    ax.set_ylim(FLOOR * 0.5, 1e-10)
    pi_ticks(ax)
    ax.axhline(2.0**-52, color="0.6", lw=0.8, ls="-.")
    ax.text(math.pi - 0.02, 2.0**-52 * 1.4, "2⁻⁵²", fontsize=7, color="0.4", ha="right")
    mark_regimes(ax, 6e-11)
    ax.set_xlabel("α")
    ax.set_ylabel("|v − exact| / exact")
    ax.set_title("Section 5.2 sweep: relative error (exact = GMP volume of the double input;\n"
                 f"zero error drawn at {FLOOR:.0e})", fontsize=10)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, 0.93), ncol=1, markerscale=2.5)
    fig.tight_layout()
    fig.savefig(path("sweep_error.png"), dpi=130)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 4.6))
    for m in ("pang", "tetia_full", "tetia", "clip"):
        for role, style in (("uv", "-"), ("vu", "--")):
            label = LABELS[m] + f" ({'U,V' if role == 'uv' else 'V,U'})"
            ax.plot(a, col(f"ns_{m}_{role}"), style, color=COLORS[m], lw=0.8, label=label)
    ax.set_yscale("log")
    ax.set_ylim(50, 5000)
    pi_ticks(ax)
    mark_regimes(ax, 4500)
    ax.set_xlabel("α")
    ax.set_ylabel("ns per call")
    with open(path("sweep.csv")) as f:
        m_ = re.search(r"median over (\d+) passes over all angles of the mean of (\d+) calls", f.readline())
    passes, reps = m_.groups() if m_ else ("?", "?")
    ax.set_title(f"Section 5.2 sweep: time per intersection (thread CPU time; median of {passes} passes,\n"
                 f"each the mean of {reps} repeated calls with the same arguments)", fontsize=10)
    ax.legend(fontsize=7, loc="lower left", ncol=2)
    fig.tight_layout()
    fig.savefig(path("sweep_time.png"), dpi=130)
    plt.close(fig)

    # Table: per method and role, per regime.
    reg = [int(rows[i]["regime"]) for i in order]
    lines = ["| method | arguments | worst rel. error, regime 1 | regime 2 | median rel. error | "
             "median ns/call, regime 1 | regime 2 | time vs tetia (regime 1 / 2) |",
             "|---|---|---:|---:|---:|---:|---:|---:|"]
    t_ref = {}
    for r in (1, 2):
        t_ref[r] = median([t for t, g in zip(col("ns_tetia_uv"), reg) if g == r])
    for m in ("tetia", "tetia_full", "clip", "pang"):
        for role in ("uv", "vu"):
            e, t = col(f"err_{m}_{role}"), col(f"ns_{m}_{role}")
            w = {r: max(x for x, g in zip(e, reg) if g == r) for r in (1, 2)}
            tm = {r: median([x for x, g in zip(t, reg) if g == r]) for r in (1, 2)}
            lines.append(f"| {m} | {'(U, V)' if role == 'uv' else '(V, U)'} | {fmt(w[1])} | "
                         f"{fmt(w[2])} | {fmt(median(e))} | {tm[1]:.0f} | {tm[2]:.0f} | "
                         f"{tm[1] / t_ref[1]:.2f} / {tm[2] / t_ref[2]:.2f} |")
    cf = [float(r["closed_form_rel_diff"]) for r in rows]
    n1, n2 = reg.count(1), reg.count(2)
    worst_at = {m: a[max(range(len(a)), key=lambda i: col(f"err_{m}_uv")[i])] for m in ("tetia", "clip", "pang")}
    out.append("### Section 5.2 sweep (Figure 11)\n")
    out.append(f"{len(rows)} angles ({n1} in regime 1, {n2} in regime 2). Errors against the exact "
               "(GMP) volume of the double input. ERRATA.md's closed form differs from it by at "
               f"most {fmt(max(cf))} relative. Worst error of (U, V) at α = "
               + ", ".join(f"{worst_at[m]:.4f} ({m})" for m in worst_at) + ".\n")
    out.extend(lines)
    # Corollary 2 bounds the absolute error: normalized by the larger tetrahedron it stays at
    # rounding level even where the intersection is a small part of it (alpha near 0 or pi).
    vol_u = 3 * math.sqrt(3) / 16 * 0.5 / 3
    ex = col("exact")
    norm = [max(vol_u, math.sin(x) / 6) for x in a]
    parts = []
    for m in ("tetia", "clip", "pang"):
        w = max(max(e1, e2) * v / n for e1, e2, v, n in
                zip(col(f"err_{m}_uv"), col(f"err_{m}_vu"), ex, norm))
        parts.append(f"{m} {fmt(w)}")
    out.append("\nWorst |v − exact| / max(|U|, |V|) over the sweep, both argument orders: "
               + ", ".join(parts) + ".")
    out.append("")


# --- Parsimony ------------------------------------------------------------------------------


def parsimony(out):
    rows = read_csv("parsimony.csv")
    out.append("### Parsimony (Sections 4.1 and 5.1)\n")
    out.append("Coordinates: 3 per edge-plane crossing flagged at line 9 of Algorithm 2 and 2 per "
               "face-line intersection flagged at line 18 (all four barycentric coordinates but the "
               "zero ones). A method that computes every intersection evaluates all of them. tetia "
               "decides their signs by inheritance, pairing (Lemma 2, Corollary 1), the straight line "
               "principle, or a direct calculation (one numerator of eq. (2) or (5), sign only), and "
               "evaluates coordinates only for the corners that lie on Y.\n")
    out.append("| workload | pairs | coordinates (3/crossing + 2/face point) | inherited | paired | "
               "straight line | computed for a sign | computed, % of all | corner coordinates "
               "evaluated | (computed + corner) / all |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    names = {"section_5_1_example": "Section 5.1 example", "section_5_2_sweep": "Section 5.2 sweep"}
    for r in rows:
        g = {k: int(v) for k, v in r.items() if k != "workload"}
        total = 3 * g["edge_crossings"] + 2 * g["face_points"]
        inh = g["edge_inherited"] + g["face_inherited"]
        paired = g["edge_paired"] + g["face_paired"]
        comp = g["edge_computed"] + g["face_computed"]
        name = names.get(r["workload"], r["workload"].replace("random_", "random, ").replace("_pairs", " pairs"))
        if r["workload"].startswith("random_"):
            name = f"random pairs (bench workload)"
        out.append(f"| {name} | {g['calls']:,} | {total:,} | {inh:,} | {paired:,} | "
                   f"{g['edge_straight_line']:,} | {comp:,} | {100 * comp / total:.1f} % | "
                   f"{g['corner_coordinates']:,} | {100 * (comp + g['corner_coordinates']) / total:.0f} % |")
    out.append("")
    out.append("Split into edges (Section 3.2) and faces (Section 3.3):\n")
    out.append("| workload | crossings | edge: inherited / paired / straight line / computed | "
               "face points | face: inherited / paired / computed | retries | inconsistencies |")
    out.append("|---|---:|---|---:|---|---:|---:|")
    for r in rows:
        g = {k: int(v) for k, v in r.items() if k != "workload"}
        name = names.get(r["workload"], "random pairs")
        out.append(f"| {name} | {g['edge_crossings']:,} | {g['edge_inherited']:,} / "
                   f"{g['edge_paired']:,} / {g['edge_straight_line']:,} / {g['edge_computed']:,} | "
                   f"{g['face_points']:,} | {g['face_inherited']:,} / {g['face_paired']:,} / "
                   f"{g['face_computed']:,} | {g['retries']} | {g['inconsistencies']} |")
    out.append("")


# --- Robustness -----------------------------------------------------------------------------

FAMILIES = [("rotated", "rotated by δ rad"), ("nudged", "nudged by δ (relative)"),
            ("shared_face", "shared face, nudged by δ"), ("kuhn_lattice", "Kuhn lattice, shifted by δ")]
ZERO_X = 1e-18  # where delta = 0 is drawn


def robustness(out):
    rows = read_csv("robustness.csv")
    methods = ("tetia", "clip", "pang")
    fig, axes = plt.subplots(2, 4, figsize=(14, 6.2), sharex=False,
                             gridspec_kw={"height_ratios": [2.2, 1]})
    for k, (fam, title) in enumerate(FAMILIES):
        ax, bx = axes[0][k], axes[1][k]
        for m in methods:
            sel = sorted((r for r in rows if r["family"] == fam and r["method"] == m),
                         key=lambda r: float(r["delta"]))
            x = [max(float(r["delta"]), ZERO_X) for r in sel]
            y = [max(float(r["worst_err"]), FLOOR) for r in sel]
            f = [100.0 * (int(r["lost"]) + int(r["invented"]) + int(r.get("inflated", 0))) / int(r["pairs"])
                 for r in sel]
            # delta = 0 (the exact degeneracy) is drawn apart, not joined to the curve.
            pos = [i for i, r in enumerate(sel) if float(r["delta"]) > 0]
            zero = [i for i, r in enumerate(sel) if float(r["delta"]) == 0]
            for a_, v in ((ax, y), (bx, f)):
                a_.plot([x[i] for i in pos], [v[i] for i in pos], "o-", ms=3, lw=1, color=COLORS[m], label=m)
                a_.plot([x[i] for i in zero], [v[i] for i in zero], "o", ms=4, color=COLORS[m])
        for a_ in (ax, bx):
            a_.set_xscale("log")
            a_.set_xlim(ZERO_X / 4, 4e-6)
        has_zero = any(float(r["delta"]) == 0 for r in rows if r["family"] == fam)
        ticks = ([ZERO_X] if has_zero else []) + [1e-16, 1e-14, 1e-12, 1e-10, 1e-8, 1e-6]
        for a_ in (ax, bx):
            a_.set_xticks(ticks)
            a_.set_xticklabels((["0"] if has_zero else []) + ["1e-16", "1e-14", "1e-12", "1e-10", "1e-8", "1e-6"],
                               fontsize=7)
            a_.minorticks_off()
        ax.set_yscale("log")
        ax.set_ylim(FLOOR * 0.5, 10)
        ax.axhline(2.0**-52, color="0.6", lw=0.8, ls="-.")
        ax.set_title(title, fontsize=10)
        bx.set_xlabel("perturbation δ", fontsize=9)
        bx.set_ylim(-2, 60)
        if k == 0:
            ax.set_ylabel("worst |v − exact| / max(|U|,|V|)", fontsize=9)
            bx.set_ylabel("lost + invented + inflated,\n% of pairs", fontsize=9)
            ax.legend(fontsize=8, loc="upper left")
    fig.suptitle("Near-degenerate pairs against the exact (GMP) volume: worst error per perturbation size "
                 f"(zero drawn at {FLOOR:.0e}; δ = 0 is the exact degeneracy)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path("robustness_error.png"), dpi=120)
    plt.close(fig)

    out.append("### Robustness (Theorem 6, Corollary 2)\n")
    out.append("Error: |v − exact| / max(|U|, |V|). Relative: |v − exact| / exact over pairs with "
               "exact ≥ 1e-3 max(|U|, |V|). Lost: exact > 1e-14 max(|U|, |V|) but v = 0 or v < exact/2. "
               "Invented: exact = 0 but v > 1e-12 max(|U|, |V|). Inflated: exact > 0 but v > 2 exact "
               "and v > 1e-12 max(|U|, |V|). Each pair counts in both argument orders (\"evaluations\" "
               "counts evaluations); \"exact > 0\" counts those with exact > 1e-14 max(|U|, |V|).\n")
    out.append("| family | method | evaluations | worst error | worst relative error | lost / exact > 0 | "
               "invented / exact = 0 | inflated | worst error at δ = 0 |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for fam, title in FAMILIES:
        for m in methods:
            sel = [r for r in rows if r["family"] == fam and r["method"] == m]
            n = sum(int(r["pairs"]) for r in sel)
            pos = sum(int(r["exact_positive"]) for r in sel)
            zero = sum(int(r["exact_zero"]) for r in sel)
            lost = sum(int(r["lost"]) for r in sel)
            inv = sum(int(r["invented"]) for r in sel)
            infl = sum(int(r.get("inflated", 0)) for r in sel)
            w = max(float(r["worst_err"]) for r in sel)
            wr = max(float(r["worst_rel"]) for r in sel)
            z = [float(r["worst_err"]) for r in sel if float(r["delta"]) == 0]
            out.append(f"| {fam} | {m} | {n:,} | {fmt(w)} | {fmt(wr)} | {lost} / {pos} | "
                       f"{inv} / {zero} | {infl} | {fmt(z[0]) if z else '-'} |")
    out.append("")


# --- Speed ----------------------------------------------------------------------------------


def bench_medians(name):
    try:
        with open(path(name)) as f:
            data = json.load(f)
    except (OSError, ValueError):
        return None
    res = {}
    for b in data.get("benchmarks", []):
        if b.get("aggregate_name", "") in ("median", "") and "items_per_second" in b:
            key = b.get("run_name", b["name"]).split("/")[0]
            if b.get("aggregate_name") == "median" or key not in res:
                res[key] = b["items_per_second"]
    return res


def rate(v):
    return f"{v / 1e6:.3g} M" if v >= 1e6 else f"{v / 1e3:.3g} k"


def speed(out):
    bp = bench_medians("bench_pairs.json")
    bc = bench_medians("bench_cgal.json")
    if not bp:
        out.append("### Speed\n\n(bench_pairs.json missing: not run)\n")
        return
    out.append("### Speed (pairs per second, one thread)\n")
    out.append("bench_pairs: 10^6 random pairs (bench/random_pairs.hpp), median of 3 repetitions. "
               "bench_cgal: the first 2000 pairs of the same workload (200 for Nef), median of 3.\n")
    ref = bp.get("BM_intersection_volume")
    clip = bp.get("BM_clip")
    rows = [("tetia `intersection_volume` (volume path)", "BM_intersection_volume", bp),
            ("tetia `intersect` (full polyhedron)", "BM_intersect", bp),
            ("tetia `intersection_moments`", "BM_intersection_moments", bp),
            ("our Sutherland-Hodgman `clip_volume`", "BM_clip", bp),
            ("our PANG-style `pang_volume`", "BM_pang", bp)]
    out.append("| method | workload | pairs/s | ns/pair | tetia volume path is faster by | vs. our clipper |")
    out.append("|---|---|---:|---:|---:|---:|")
    for label, key, src in rows:
        v = src.get(key)
        if v:
            out.append(f"| {label} | 10^6 random | {rate(v)} | {1e9 / v:,.0f} | {ref / v:.2f}x | "
                       f"{v / clip:.2f}x |")
    if bc:
        tref = bc.get("BM_tetia_intersection_volume")
        for label, key in (("tetia `intersection_volume` (same sample)", "BM_tetia_intersection_volume"),
                           ("CGAL `PMP::clip`, EPECK", "BM_cgal_clip_epeck"),
                           ("CGAL `PMP::clip`, EPICK", "BM_cgal_clip_epick"),
                           ("CGAL `Nef_polyhedron_3`, EPECK", "BM_cgal_nef")):
            v = bc.get(key)
            if v:
                n = "first 200" if "nef" in key else "first 2000"
                out.append(f"| {label} | {n} | {rate(v)} | {1e9 / v:,.0f} | {tref / v:,.0f}x | "
                           f"{v / clip:.2g}x |")
    else:
        out.append("\n(bench_cgal.json missing: CGAL not found or not run)")
    out.append("")


def main():
    out = []
    info = path("run-info.txt")
    if os.path.exists(info):
        out.append("### Run\n")
        out.append("```")
        out.append(open(info).read().rstrip())
        out.append("```\n")
    sweep(out)
    parsimony(out)
    robustness(out)
    speed(out)
    with open(path("tables.md"), "w") as f:
        f.write("<!-- Generated by scripts/paper_plots.py from the CSV/JSON files in this folder. -->\n\n")
        f.write("\n".join(out) + "\n")
    print(f"wrote {path('sweep_error.png')}, {path('sweep_time.png')}, "
          f"{path('robustness_error.png')}, {path('tables.md')}")


if __name__ == "__main__":
    main()
