#!/usr/bin/env bash
# A broken variant of an assignment is its reference plus one mistake:
# assignments/<name>/broken/<variant>/ holds NOTE.md, expected.yaml and
# mistake.patch, a unified diff against the files of <name>/reference/.
# This script turns the patch into a project folder and back
# (docs/grading.md, "Broken variants"):
#
#   broken-variant.sh ASSIGNMENT VARIANT DIR
#       writes the variant into DIR (created if needed; files of the same
#       name are replaced, others left alone): the reference's files with
#       mistake.patch applied, and the variant's NOTE.md and expected.yaml.
#       DIR is then a project as `syrof new` writes it, gradable as it
#       stands. The build runs this for every variant
#       (tests/grader/assignment/CMakeLists.txt).
#   broken-variant.sh --write-patch ASSIGNMENT VARIANT DIR
#       the other way: writes broken/VARIANT/mistake.patch from the
#       differences between the reference's files and DIR's (after editing
#       a variant written by the first form, or a copy of the reference).
#
# ASSIGNMENT is a folder holding assignment.yaml, or a name under this
# source tree's assignments/. A reference is a flat folder; a patch changes
# its files and adds or removes none. The patch must apply exactly (no fuzz;
# a hunk may only have moved), so a changed reference never silently puts
# the mistake somewhere else: when a patch no longer applies this fails and
# names the assignment, the variant and the file.
set -euo pipefail

me=broken-variant.sh
usage() {
  echo "usage: $me ASSIGNMENT VARIANT DIR" >&2
  echo "       $me --write-patch ASSIGNMENT VARIANT DIR" >&2
  exit 2
}

mode=write-variant
if [ "${1:-}" = --write-patch ]; then
  mode=write-patch
  shift
fi
[ $# -eq 3 ] || usage
assignment_arg=$1
variant=$2
dir=$3
if [[ ! $variant =~ ^[A-Za-z0-9_][A-Za-z0-9_.-]*$ ]]; then
  echo "$me: '$variant' is not a variant's name (letters, digits, '_', '-', '.')" >&2
  exit 2
fi

if [ -f "$assignment_arg/assignment.yaml" ]; then
  assignment_dir=$assignment_arg
elif [ -f "$(dirname "$0")/../assignments/$assignment_arg/assignment.yaml" ]; then
  assignment_dir="$(dirname "$0")/../assignments/$assignment_arg"
else
  echo "$me: '$assignment_arg' is neither a folder holding assignment.yaml nor an assignment in assignments/" >&2
  exit 2
fi
assignment_dir=$(cd "$assignment_dir" && pwd)
assignment=$(basename "$assignment_dir")
reference_dir=$assignment_dir/reference
variant_dir=$assignment_dir/broken/$variant
[ -d "$reference_dir" ] || { echo "$me: assignment '$assignment' has no reference/ folder" >&2; exit 2; }

# The reference's files a variant is made of: every regular file at the top
# of reference/ but expected.yaml (the variant has its own) and dot files; a
# build/ folder from building the reference in place is left out.
reference_files=()
for path in "$reference_dir"/*; do
  name=$(basename "$path")
  if [ -f "$path" ] && [ "$name" != expected.yaml ]; then reference_files+=("$name"); fi
done

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT

if [ "$mode" = write-patch ]; then
  [ -d "$dir" ] || { echo "$me: no folder '$dir' to take the variant's files from" >&2; exit 2; }
  for name in "${reference_files[@]}"; do
    [ -f "$dir/$name" ] || continue
    # diff exits 1 when the files differ. Labels instead of paths and times
    # keep the patch the same bytes wherever it is made.
    diff -u --label "a/$name" --label "b/$name" "$reference_dir/$name" "$dir/$name" >> "$stage/mistake.patch" ||
      [ $? -eq 1 ]
  done
  for path in "$dir"/*.c "$dir"/*.cc "$dir"/*.cpp "$dir"/*.cxx "$dir"/*.h; do
    if [ -f "$path" ] && [ ! -f "$reference_dir/$(basename "$path")" ]; then
      echo "$me: $path is not in $assignment's reference: a patch adds no file, so it is left out" >&2
    fi
  done
  if [ ! -s "$stage/mistake.patch" ]; then
    echo "$me: the files in '$dir' are the reference's: a variant must differ from it" >&2
    exit 1
  fi
  mkdir -p "$variant_dir"
  cp "$stage/mistake.patch" "$variant_dir/mistake.patch"
  echo "$me: wrote $variant_dir/mistake.patch"
  exit 0
fi

if [ ! -f "$variant_dir/mistake.patch" ]; then
  known=$(cd "$assignment_dir" && ls -d broken/*/mistake.patch 2>/dev/null | cut -d/ -f2 | paste -sd ' ' || true)
  echo "$me: assignment '$assignment' has no broken variant '$variant' (no broken/$variant/mistake.patch);" \
       "its variants: ${known:-none}" >&2
  exit 2
fi

# Made in the stage, so a patch that applies only in part leaves DIR as it was.
for name in "${reference_files[@]}"; do cp "$reference_dir/$name" "$stage/"; done
if ! output=$(patch -d "$stage" -p1 --batch --forward --fuzz=0 --no-backup-if-mismatch --reject-file=- \
                    -i "$variant_dir/mistake.patch" 2>&1); then
  # The files that failed: patch names each ("patching file gather.c", or
  # "|+++ b/gather.c" above "can't find file to patch") before its verdict.
  failed=$(printf '%s\n' "$output" | awk '
    /^patching file / { file = substr($0, 15) }
    /^\|\+\+\+ / { file = $2; sub(/^b\//, "", file) }
    /FAILED|ignored/ && file != "" && !(file in seen) { seen[file] = 1; list = list (list == "" ? "" : ", ") "reference/" file }
    END { print list }')
  echo "$me: assignment '$assignment', broken variant '$variant': mistake.patch does not apply${failed:+ to $failed}" >&2
  printf '%s\n' "$output" | sed 's/^/  patch: /' >&2
  echo "  Make the variant as it should now be and write its patch again:" \
       "$me --write-patch (docs/grading.md, \"Broken variants\")." >&2
  exit 1
fi
changed=0
for name in "${reference_files[@]}"; do
  if ! cmp -s "$reference_dir/$name" "$stage/$name"; then changed=1; fi
done
if [ $changed -eq 0 ]; then
  echo "$me: assignment '$assignment', broken variant '$variant': mistake.patch changes none of the" \
       "reference's files; a variant must differ from its reference" >&2
  exit 1
fi
for name in NOTE.md expected.yaml; do
  if [ -f "$variant_dir/$name" ]; then cp "$variant_dir/$name" "$stage/"; fi
done
mkdir -p "$dir"
cp "$stage"/* "$dir/"
