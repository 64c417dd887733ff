#!/bin/sh
# The seed report's tables 5.1 and 5.4 (shared/seed/report_fr.txt) measured with this
# project's solver, the report's own figures beside ours:
#   5.1  bcsstk16 and the fine torus matrix: up-, left-looking (and supernodal) factorization
#        with the natural, AMD and METIS orderings: nnz(L), fill, time, residual, CHOLMOD;
#   5.4  torus_pull_fine (WCC, partial strategy) per step: elements re-rotated, columns and
#        flops recomputed, partial against full refactorization, cost of the error estimate.
#
#   sh benchmarks/report_tables.sh    # about 6 minutes on 2 cores; writes doc/report_tables/
#
# Environment: BUILD (default build), OUT (default doc/report_tables), WORK (the matrices
# and the runs' logs, default output/report_tables), REPEAT (factorizations per cell of 5.1,
# default 5), MAX_SECONDS (a cell of 5.1 stops repeating once its factorizations took this
# long, default 20: the natural ordering of the torus takes two minutes column by column).
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
build=${BUILD:-build}
out=${OUT:-doc/report_tables}
work=${WORK:-output/report_tables}
repeat=${REPEAT:-5}
max_seconds=${MAX_SECONDS:-20}
# One thread everywhere (the programs also restart themselves so, see doc/benchmarks.md).
export OMP_THREAD_LIMIT=${OMP_THREAD_LIMIT:-1} OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
mkdir -p "$out" "$work"

scene=parameters/torus_pull_fine.prm
machine="$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(env -u OMP_THREAD_LIMIT -u OMP_NUM_THREADS nproc) cores, $(date -u +%Y-%m-%d)"
# The 1-minute load average: others' work on a shared machine slows the measurements.
load_average() { cut -d ' ' -f 1 /proc/loadavg; }

# The opening of table TABLE's Markdown: its title and how it was produced (the paragraph
# goes on). Needs load_before, the load average when its measurements began.
opening() {
  cat << EOF
# Table $1 of the report, with this project's solver

Produced by \`sh benchmarks/report_tables.sh\` (BUILD=$build, a
$(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt") build; OMP_THREAD_LIMIT=1,
OPENBLAS_NUM_THREADS=1; $machine; load average $load_before before, $(load_average) after:
a shared machine, so compare ratios, not seconds).
EOF
}

# ---------------------------------------------------------------------------------------
# Table 5.1
# ---------------------------------------------------------------------------------------

# The report's figures (section 5.1, tests 4 and 5) for MATRIX/METHOD/ORDERING:
# "fill time residue", or nothing where the report has no such row.
report_5_1() {
  case $1 in
    bcsstk16/up/amd) echo "253.41 0.081539 1.19e-22" ;;
    bcsstk16/left/amd) echo "253.41 0.090661 1.19e-22" ;;
    torus/up/natural) echo "7064.95 56.30 2.22e-15" ;;
    torus/up/amd) echo "733.34 0.86 1.05e-15" ;;
    torus/left/natural) echo "7064.95 57.55 2.27e-15" ;;
    torus/left/amd) echo "733.34 0.88 9.50e-16" ;;
  esac
}

# The torus: the report's is a 10260 x 10260 matrix of SOFA's fine torus (3420 vertices,
# 15856 tets, 402,516 entries in both triangles); ours is the same A = M + dt^2 K on
# meshes/torus_fine.msh, the mesh of torus_pull_fine.prm (3445 vertices, 14625 tets).
torus_mesh=$(sed -n 's/^ *set File *= *//p' "$scene")
results="$work/table_5_1.txt"

# awk: the fields of a line of warpchol-factor, f[KEY] = VALUE.
awk_fields='{ delete f; for (i = 1; i <= NF; i++) { split($i, kv, "="); f[kv[1]] = kv[2] } }'

# Field KEY of the first line of MATRIX in the results.
first_field() {
  awk -v matrix="$1" -v key="$2" '
    $1 == "matrix=" matrix { for (i = 1; i <= NF; i++) if (index($i, key "=") == 1) { print substr($i, length(key) + 2); exit } }' "$results"
}

# Rows of the markdown tables from the key=value lines. The report's fill is nnz(L) over
# the entries of A in both triangles (fill_full): bcsstk16 with AMD has 290,378 of them and
# 253.41 % gives nnz(L) = 735,847, the size of its AMD factor; over tril(A) it would be
# 498 %.
table_5_1_rows() {
  awk -v matrix="$1" "$awk_fields"'
    f["matrix"] != matrix { next }
    {
      n = split(f["report"], report, ",")
      printf "| %s | %s | %d | %.2f %% | %s | %.3g | %d | %s | %.3g | %.2f | %.2e | %s |\n",
        f["method"], f["ordering"], f["nnz_l"], 100 * f["fill_full"], (n ? report[1] " %" : ""),
        f["factor_median_s"], f["repeats"], (n ? report[2] : ""), f["cholmod_median_s"],
        f["factor_median_s"] / f["cholmod_median_s"], f["residual"], (n ? report[3] : "")
    }' "$results"
}

# The ratios that do not depend on the machine: ours against the report's.
table_5_1_ratios() {
  awk -v matrix="$1" "$awk_fields"'
    f["matrix"] != matrix { next }
    {
      key = f["method"] "/" f["ordering"]; time[key] = f["factor_median_s"]
      if (split(f["report"], report, ",")) report_time[key] = report[2]
    }
    function row(label, a, b) {
      printf "| %s | %.3g | %s |\n", label, time[a] / time[b],
        (a in report_time && b in report_time) ? sprintf("%.3g", report_time[a] / report_time[b]) : ""
    }
    END {
      split("natural amd metis", orderings, " ")
      for (o = 1; o <= 3; o++)
        row("left / up, " orderings[o], "left/" orderings[o], "up/" orderings[o])
      for (o = 1; o <= 3; o++)
        row("supernodal / left, " orderings[o], "supernodal/" orderings[o], "left/" orderings[o])
      row("natural / AMD, up", "up/natural", "up/amd")
      row("natural / AMD, left", "left/natural", "left/amd")
      row("METIS / AMD, left", "left/metis", "left/amd")
    }' "$results"
}

# Table 5.1: measure (one key=value line of warpchol-factor per matrix, method and
# ordering, into $results), then write the markdown.
table_5_1() {
  load_before=$(load_average)
  "$build/warpchol-torus-matrix" --mesh "parameters/$torus_mesh" --output "$work/torus_fine.mtx" > /dev/null
  : > "$results"
  for matrix in bcsstk16 torus; do
    case $matrix in
      bcsstk16) file=tests/data/bcsstk16.mtx ;;
      torus) file=$work/torus_fine.mtx ;;
    esac
    for method in up left supernodal; do
      for ordering in natural amd metis; do
        echo "== 5.1: $matrix $method $ordering" >&2
        printf 'matrix=%s report=%s ' "$matrix" "$(report_5_1 "$matrix/$method/$ordering" | tr ' ' ,)" >> "$results"
        "$build/warpchol-factor" "$file" --method "$method" --ordering "$ordering" --changed-fraction 0 \
          --compare cholmod --repeat "$repeat" --max-seconds "$max_seconds" >> "$results"
      done
    done
  done

  {
    opening 5.1
    cat << EOF
Each row is one
\`warpchol-factor MATRIX --method M --ordering O --changed-fraction 0 --compare cholmod
--repeat $repeat --max-seconds $max_seconds\`; the raw key=value lines are in
\`$results\`.

Columns: **nnz(L)** entries of the factor, diagonal included; **fill** nnz(L) / nnz(A) with
A's entries counted in both triangles, the report's definition (its 253.41 % for bcsstk16
with AMD is nnz(L) = 735,847 over 290,378 entries; over tril(A) it would be about twice
that); **time** the median of the numeric factorizations (the symbolic analysis is not
counted; **runs** of them: fewer than $repeat where they took more than $max_seconds s);
**CHOLMOD** the median time of CHOLMOD's supernodal factorization with the same permutation
and BLAS, alternating with ours, and **/ CHOLMOD** ours over it; **residual**
\`||Ax - b||_2 / ||b||_2\` with b = A 1 (the report does not define its *residue*; its
1.19e-22 for bcsstk16 is below rounding, so it is not a relative residual). *report*
columns quote the report's section 5.1; empty where it has no such row (it ran natural
ordering on the torus only, and no METIS, no supernodal method). Our AMD and METIS order
the graph of the mesh vertices (3 dofs each) where the report ran AMD on the scalar graph,
hence slightly different fill.

The report's torus matrix is SOFA's fine torus (10260 unknowns, 3420 vertices, 15856 tets,
402,516 entries); ours is A = M + dt^2 K of \`meshes/torus_fine.msh\` (the mesh of
\`parameters/torus_pull_fine.prm\`: 10335 unknowns, 3445 vertices, 14625 tets, written by
\`warpchol-torus-matrix --mesh\`). Its natural ordering is the numbering of the mesh file's
vertices (Gmsh's; the report's was SOFA's), 3 dofs each.

EOF
    for matrix in bcsstk16 torus; do
      n=$(first_field "$matrix" n)
      case $matrix in
        bcsstk16) title="bcsstk16 (HB, a 3D dam)" ;;
        torus) title="The fine torus" ;;
      esac
      echo "## $title: $n x $n, $((2 * $(first_field "$matrix" nnz_a) - n)) entries"
      echo
      echo "| method | ordering | nnz(L) | fill | *report* | time (s) | runs | *report* (s) | CHOLMOD (s) | / CHOLMOD | residual | *report* |"
      echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
      table_5_1_rows "$matrix"
      echo
      echo "| time ratio | ours | *report* |"
      echo "|---|---:|---:|"
      table_5_1_ratios "$matrix"
      echo
    done
  } > "$out/table_5_1.md.tmp"
  mv "$out/table_5_1.md.tmp" "$out/table_5_1.md"
  cat "$out/table_5_1.md"
}

# ---------------------------------------------------------------------------------------
# Table 5.4
# ---------------------------------------------------------------------------------------

# The report's table (section 5.4): left-looking partial refactorization, AMD, its fine
# torus; a full factorization took 0.88 s (section 5.1).
report_full_seconds=0.88
# awk: the median of values[1..n] (sorts them; 0 if n = 0).
awk_median='
  function median(values, n,    i, j, swap) {
    for (i = 2; i <= n; i++)
      for (j = i; j > 1 && values[j - 1] > values[j]; j--) {
        swap = values[j]; values[j] = values[j - 1]; values[j - 1] = swap
      }
    return n == 0 ? 0 : n % 2 ? values[(n + 1) / 2] : (values[n / 2] + values[n / 2 + 1]) / 2
  }'
cat > "$work/report_5_4.csv" << EOF
step,columns_pct,partial_s,elements_pct,estimate_s
5,21.23,0.646951,0.99,0.024149
6,37.19,0.696675,0.99,0.014210
7,47.81,0.730343,4.84,0.024937
8,50.18,0.723504,3.51,0.024989
9,51.49,0.757316,3.14,0.025076
11,54.33,0.748301,3.36,0.025338
12,57.28,0.722368,6.09,0.014967
14,59.59,0.737213,3.82,0.015789
15,61.40,0.746773,3.35,0.025425
17,66.26,0.739385,2.99,0.025151
18,69.30,0.745897,4.19,0.018517
23,73.77,0.745221,2.73,0.254529
25,75.99,0.749349,2.90,0.014915
27,78.45,0.746261,2.94,0.025447
48,83.36,0.763928,4.41,0.026418
EOF

# Run the scene as NAME with ORDERING, METHOD, model TYPE for STEPS steps [at THRESHOLD]:
# a parameter file that includes the scene and overrides these entries (and its mesh path,
# relative to the scene's folder), logging every step to WORK/NAME/log.csv.
run_scene() {
  {
    echo "include $root/$scene"
    printf 'subsection Mesh\n  set File = %s\nend\n' "$root/parameters/$torus_mesh"
    printf 'subsection Time stepping\n  set Number of steps = %s\nend\n' "$5"
    printf 'subsection Model\n  set Type = %s\n  set Strategy = partial\n' "$4"
    [ $# -lt 6 ] || printf '  set Rerotation threshold = %s\n' "$6"
    printf 'end\nsubsection Solver\n  set Ordering = %s\n  set Method = %s\n  set Threads = 1\nend\n' "$2" "$3"
    printf 'subsection Output\n  set Directory = %s\n  set Scene = %s\n' "$work" "$1"
    printf '  set VTU interval = 0\n  set Write log = true\n  set Progress = off\nend\n'
  } > "$work/$1.prm"
  echo "== 5.4: $1" >&2
  "$build/warpchol" "$work/$1.prm" > "$work/$1.txt"
}

# From the report's CSV, a corotational log (full factorizations) and a WCC log: MODE steps
# prints the rows of the per-step table, MODE summary one row of the summary table.
# Columns are found by their names in the logs' headers.
step_log_rows() {
  awk -F, -v mode="$1" -v label="$2" -v report_full="$report_full_seconds" "$awk_median"'
    function field(name) { return $(column[name]) }
    FNR == 1 { file++; split("", column); for (i = 1; i <= NF; i++) column[$i] = i; next }
    file == 1 {
      s = field("step"); report_steps[++n_report] = s
      r_columns[s] = field("columns_pct"); r_partial[s] = field("partial_s")
      r_elements[s] = field("elements_pct"); r_estimate[s] = field("estimate_s")
      next
    }
    file == 2 {
      if (field("refactorized") == 1) full[++n_full] = field("t_factor")
      corotational_step[++n_corotational] = field("t_step")
      next
    }
    {
      s = field("step"); refactorized[s] = field("refactorized")
      elements[s] = field("elements_rerotated_pct"); columns[s] = field("columns_recomputed_pct")
      flops[s] = field("flops_recomputed_pct"); partial[s] = field("t_factor")
      estimate[s] = field("t_error_estimate"); step_time[s] = field("t_step")
    }
    function row(name, el, co, fl, pa, es, st, r_el, r_co, r_pa, r_es) {
      printf "| %s | %.2f %% | %.1f %% | %.1f %% | %.3g | %.2f | %.3g | %.1f %% | %.2f %% | %.2f %% | %.3g | %.2f | %.3g |\n",
        name, el, co, fl, pa, pa / full_seconds, es, 100 * es / st, r_el, r_co, r_pa, r_pa / report_full, r_es
    }
    END {
      full_seconds = median(full, n_full)
      if (mode == "full") { printf "%.3g s (median of %d), an exact corotational step %.3g s", full_seconds, n_full, median(corotational_step, n_corotational); exit }
      # Medians over the report steps, and over every step of ours that refactorized.
      n = 0
      for (k = 1; k <= n_report; k++) {
        s = report_steps[k]
        if (mode == "steps")
          row(s, elements[s], columns[s], flops[s], partial[s], estimate[s], step_time[s],
              r_elements[s], r_columns[s], r_partial[s], r_estimate[s])
        ++n; a_el[n] = elements[s]; a_co[n] = columns[s]; a_fl[n] = flops[s]; a_pa[n] = partial[s]
        a_es[n] = estimate[s]; a_st[n] = step_time[s]; b_el[n] = r_elements[s]; b_co[n] = r_columns[s]
        b_pa[n] = r_partial[s]; b_es[n] = r_estimate[s]
      }
      r_el = median(b_el, n); r_co = median(b_co, n); r_pa = median(b_pa, n); r_es = median(b_es, n)
      if (mode == "steps")
        row("median of these", median(a_el, n), median(a_co, n), median(a_fl, n), median(a_pa, n),
            median(a_es, n), median(a_st, n), r_el, r_co, r_pa, r_es)
      m = 0
      for (s in refactorized)
        if (refactorized[s] == 1) {
          ++m; c_el[m] = elements[s]; c_co[m] = columns[s]; c_fl[m] = flops[s]; c_pa[m] = partial[s]
          c_es[m] = estimate[s]; c_st[m] = step_time[s]
        }
      el = median(c_el, m); co = median(c_co, m); fl = median(c_fl, m); pa = median(c_pa, m)
      es = median(c_es, m); st = median(c_st, m)
      if (mode == "steps")
        printf "| median of all %d steps that refactorized | %.2f %% | %.1f %% | %.1f %% | %.3g | %.2f | %.3g | %.1f %% | | | | | |\n",
          m, el, co, fl, pa, pa / full_seconds, es, 100 * es / st
      else
        printf "| %s | %.2f %% | %.1f %% | %.1f %% | %.3g | %.3g | %.2f | %.3g | %.1f %% | %.3f | %.3g | %.2f |\n",
          label, el, co, fl, pa, full_seconds, pa / full_seconds, es, 100 * es / st, es / full_seconds,
          st, st / median(corotational_step, n_corotational)
    }' "$work/report_5_4.csv" "$3" "$4"
}

# The scene's solver (METIS, supernodal) and the report's (AMD, column-by-column
# left-looking), each at threshold 1 (the scene's until issue 26, which moved it to inf,
# where WCC re-rotates nothing) and at 0.3, where about as many elements are re-rotated per
# step as in the report's run (1-6 %).
threshold=1
solvers="metis:supernodal amd:left"
thresholds="$threshold 0.3"

# Table 5.4: run the scene with each solver and threshold, then write the markdown.
table_5_4() {
  load_before=$(load_average)
  # The full factorizations: exact corotational runs of 10 steps just before and just after
  # each WCC run, so that both see about the same load of the (shared) machine.
  for solver in $solvers; do
    ordering=${solver%%:*} method=${solver#*:}
    for t in $thresholds; do
      name=${ordering}_${method}_$t
      run_scene "corotational_before_$name" "$ordering" "$method" corotational 10
      run_scene "wcc_$name" "$ordering" "$method" warp_canceling 100 "$t"
      run_scene "corotational_after_$name" "$ordering" "$method" corotational 10
      { cat "$work/corotational_before_$name/log.csv"; sed 1d "$work/corotational_after_$name/log.csv"; } \
        > "$work/corotational_$name.csv"
    done
  done

  {
    opening 5.4
    cat << EOF
It runs the scene \`$scene\` (the report's fine torus pulled by a
tool, 100 steps of 0.01 s) with WCC and the partial strategy (the WCC system solved
directly with the partially refactorized factor, as in the report) by \`warpchol\` with a
parameter file that includes the scene and overrides the model, the solver and the output
(\`$work/NAME.prm\`; per-step logs in \`$work/NAME/log.csv\`). Four runs: the
scene's solver (METIS, supernodal) and the report's (AMD, column-by-column left-looking),
each at the scene's threshold $threshold and at 0.3, where about as many elements are
updated per step as in the report's run (1-6 %). The full factorization time of each run
is the median of the 20 factorizations of two exact corotational runs of the same scene
and solver, 10 steps just before and 10 just after it, so that both see about the same
load of the machine.

Columns: **elements re-rotated** the share of tets whose contribution to A was recomputed
(\`elements_rerotated_pct\`); **columns** and **flops** the share of the columns of L and of
the flops of a full factorization that the partial refactorization recomputed
(\`columns_recomputed_pct\`, \`flops_recomputed_pct\`); **partial** the seconds of the
partial refactorization (\`t_factor\`) and **/ full** over a full one; **estimate** the
seconds of the per-element error estimate (\`t_error_estimate\`) and **/ step** its share of
the step (\`t_step\`); **step** the seconds of a WCC step and **/ corotational step**
over one of the exact corotational runs (same solver: does WCC pay?). *report* columns
quote the report's table at its steps (its "cost error calculation" may include the
update of the elements' matrices; its step 23's 0.25 s looks like an outlier) and divide
its partial times by its full left-looking AMD factorization, 0.88 s; it has no flops
column. Medians are over the listed steps or over every step of ours that refactorized
(the first step has nothing to update).

## Summary: medians over the steps that refactorized

| solver, threshold | elements re-rotated | columns | flops | partial (s) | full (s) | partial / full | estimate (s) | estimate / step | estimate / full | step (s) | step / corotational step |
|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|
EOF
    for solver in $solvers; do
      ordering=${solver%%:*} method=${solver#*:}
      for t in $thresholds; do
        step_log_rows summary "$ordering $method, $t" "$work/corotational_${ordering}_${method}_$t.csv" \
          "$work/wcc_${ordering}_${method}_$t/log.csv"
      done
    done
    awk -F, -v full="$report_full_seconds" "$awk_median"'
      NR > 1 { ++n; co[n] = $2; pa[n] = $3; el[n] = $4; es[n] = $5 }
      END {
        printf "| *report: amd left-looking (its %d steps)* | *%.2f %%* | *%.1f %%* | | *%.3g* | *%.3g* | *%.2f* | *%.3g* | | *%.3f* | | |\n",
          n, median(el, n), median(co, n), median(pa, n), full, median(pa, n) / full, median(es, n), median(es, n) / full
      }' "$work/report_5_4.csv"
    for solver in $solvers; do
      ordering=${solver%%:*} method=${solver#*:}
      for t in $thresholds; do
        echo
        echo "## $ordering, $method, threshold $t: the report's steps"
        echo
        echo "Full factorization: $(step_log_rows full "" "$work/corotational_${ordering}_${method}_$t.csv" \
          "$work/wcc_${ordering}_${method}_$t/log.csv")."
        echo
        echo "| step | elements re-rotated | columns | flops | partial (s) | / full | estimate (s) | / step | *report* elements | *report* columns | *report* partial (s) | *report* / full | *report* estimate (s) |"
        echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
        step_log_rows steps "" "$work/corotational_${ordering}_${method}_$t.csv" "$work/wcc_${ordering}_${method}_$t/log.csv"
      done
    done
  } > "$out/table_5_4.md.tmp"
  mv "$out/table_5_4.md.tmp" "$out/table_5_4.md"
  cat "$out/table_5_4.md"
}

# TABLES: which tables to make (default both).
for table in ${TABLES:-5.1 5.4}; do
  case $table in
    5.1) table_5_1 ;;
    5.4) table_5_4 ;;
    *) echo "report_tables.sh: TABLES: no table $table (5.1, 5.4)" >&2; exit 2 ;;
  esac
done
