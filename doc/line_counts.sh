#!/bin/sh
# The lines of the code per folder, as the markdown table of doc/ARCHITECTURE.md: each room
# of the library (source/X with its headers include/warpchol/X) in the order of its layers
# (tests/layers_point_one_way.cmake), then programs/; its files, its lines and its share
# of the whole (source, include and programs). Run from anywhere: doc/line_counts.sh
set -eu
cd "$(dirname "$0")/.."

layers=$(sed -n 's/^set(layers \(.*\))$/\1/p' tests/layers_point_one_way.cmake)
# A folder of source/ that the layers do not list yet is counted too, after them.
unlisted=$(for folder in $(ls source); do
             case " $layers " in *" $folder "*) ;; *) echo "$folder" ;; esac
           done)

# "FOLDER FILES LINES" for the C++ files of the given paths.
count() {
  name=$1
  shift
  files=$(find "$@" -type f \( -name '*.h' -o -name '*.cc' \) 2>/dev/null | sort)
  if [ -z "$files" ]; then
    echo "$name 0 0"
  else
    echo "$name $(echo "$files" | wc -l) $(cat $files | wc -l)"
  fi
}

{
  for folder in $layers $unlisted; do
    count "$folder/" "source/$folder" "include/warpchol/$folder"
  done
  count "programs/" programs
} | awk '
  { name[NR] = $1; files[NR] = $2; lines[NR] = $3; total_files += $2; total += $3 }
  END {
    print "| folder | files | lines | share |"
    print "|---|---:|---:|---:|"
    for (i = 1; i <= NR; ++i)
      printf "| `%s` | %d | %d | %.1f %% |\n", name[i], files[i], lines[i], 100 * lines[i] / total
    printf "| total | %d | %d | 100 %% |\n", total_files, total
  }'
