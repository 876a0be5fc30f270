#!/usr/bin/env bash
# A newcomer's first hour, end to end, from this tree's build: the commands
# of the docs, extracted from them and run as written, so the docs cannot
# drift from what works.
#  0. README.md's "Your own app" block (syrof new, build, run).
#  1. The student (assignments/strongest/README.md, every ```sh student
#     block, in order, in one shell, HOME a fresh folder, PATH without the
#     build tree until the README's own line adds it): copy the starter out
#     of the tree, build it, run a public scenario, view it, grade it, run
#     the search test; paste the report's replay lines (a run's and the
#     search test's) as printed. Then the page is opened in headless
#     Chromium and a screenshot taken. Every other assignment's README likewise, but for
#     its grade line (checked to be strongest's with its name).
#  2. The instructor (docs/grading.md, every ```sh instructor block, in an
#     empty folder with syrof on PATH): `syrof assignment new`, a search
#     test switched on, `syrof assignment check`, a class of three graded
#     (one does not compile).
#  3. What a student is handed holds no hidden scenario's content and no
#     absolute path; the replay's page has its verdict banner.
# Every failed check is listed at the end (the script goes on after one).
# `/path/to/syrof` in the docs stands for the clone (SOURCE_DIR) and
# `/path/to/syrof/build/bin` for BIN_DIR.
#   walkthrough_test.sh SOURCE_DIR BIN_DIR CHROMIUM
set -uo pipefail
source_dir=$1
bin_dir=$2
chromium=${3:-}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=()
fail() {
  echo "walkthrough: FAIL: $*" >&2
  failures+=("$*")
}
step() { echo "walkthrough: $*"; }
started=$(date +%s)

# Every ```sh TAG block of FILE, in order, with the clone's placeholder
# replaced.
blocks() {
  awk -v open="\`\`\`sh $2" '$0 == open {on = 1; next} on && /^```$/ {on = 0; next} on {print}' "$1" |
    sed -e "s|/path/to/syrof/build/bin|$bin_dir|g" -e "s|/path/to/syrof|$source_dir|g"
}

# FILE holds no absolute path of this machine's: the work folder, nor any
# path under /work/, /tmp/ or /root/.
no_absolute_paths() {
  local file=$1
  for needle in "$work" /work/ /tmp/ /root/; do
    if grep -qF -- "$needle" "$file"; then
      fail "$file holds an absolute path ($needle): $(grep -oF -- "$needle" "$file" | head -1)..."
      grep -o -- "[^\"' <>]*${needle}[^\"' <>]*" "$file" | head -3 >&2
    fi
  done
}

base_path=/usr/local/bin:/usr/bin:/bin

# 0. README.md's "Your own app": its ```sh block, in a fresh folder.
own_app=$(awk '/^## Your own app$/ {on = 1; next} on && /^## / {exit} on {print}' "$source_dir/README.md" |
  awk '/^```sh$/ {on = 1; next} on && /^```$/ {on = 0; next} on {print}' |
  sed -e "s|/path/to/syrof/build/bin|$bin_dir|g" -e "s|/path/to/syrof|$source_dir|g")
[ -n "$own_app" ] || fail "no \`\`\`sh block in README.md's 'Your own app'"
mkdir -p "$work/own_app"
(cd "$work/own_app" && PATH=$base_path bash -euo pipefail -c "$own_app") > "$work/own_app.log" 2>&1 ||
  { fail "README.md's 'Your own app' failed"; tail -15 "$work/own_app.log" >&2; }
[ -s "$work/own_app/myapp/out/myapp/metrics.json" ] || fail "README.md's 'Your own app' left no out/myapp/metrics.json"
step "README.md's 'Your own app' ran as written"

# 1. The student.
readme="$source_dir/assignments/strongest/README.md"
student=$(blocks "$readme" student)
[ -n "$student" ] || fail "no \`\`\`sh student block in $readme"
export HOME="$work/home"
mkdir -p "$HOME"
step "the student, from $readme:"
echo "$student"
echo "---"
# `syrof search` exits 1 when a pattern breaks the app, which is what it
# must say of the starter (checked below); any other failure is the docs'.
search_may_break='syrof() { command syrof "$@" || { local status=$?; [ "$1" = search ] && [ $status = 1 ] || return $status; }; }'
(cd "$work" && PATH=$base_path bash -euo pipefail -c "$search_may_break"$'\n'"$student") ||
  fail "a student command failed (above)"
echo "---"
project="$HOME/strongest"
for file in build/libstrongest.so out/metrics.json out/replay out/replay.html out/join_4-search; do
  [ -e "$project/$file" ] || fail "the student's $file is missing"
done
[ -s "$project/out/join_4-search/counterexample.yaml" ] ||
  fail "syrof search wrote no counterexample for the starter, which holds still"
grep -q 'id="verdict"' "$project/out/replay.html" 2>/dev/null ||
  fail "out/replay.html has no verdict banner (id=\"verdict\")"
mapfile -t student_reports < <(find "$project/grade-out" -name report.html 2>/dev/null)
[ "${#student_reports[@]}" -gt 0 ] || fail "syrof grade wrote no report.html under $project/grade-out"
for report in "${student_reports[@]}"; do no_absolute_paths "$report"; done
no_absolute_paths "$project/out/replay.html"
# The report's replay lines, pasted in the project's folder as printed: the
# first run's and the search test's (the starter fails both).
mapfile -t replays < <(grep -ho '"replay_command": "syrof [a-z]* [^"]*"' "$project"/grade-out/*/grade.json 2>/dev/null |
  sed 's/^"replay_command": "\(.*\)"$/\1/' | awk '!seen[$2]++')
[ "${#replays[@]}" = 2 ] || fail "grade.json has no replay line of a run and of the search test: ${replays[*]}"
for replay in "${replays[@]}"; do
  (cd "$project" && PATH="$bin_dir:$base_path" bash -euo pipefail -c "$search_may_break"$'\n'"$replay") \
    > "$work/replay.log" 2>&1 || { fail "the report's '$replay' failed in the project's folder"; tail -5 "$work/replay.log" >&2; }
done
[ -n "$(find "$project/rerun" -name counterexample.yaml 2>/dev/null)" ] || fail "the search test's replay line wrote no counterexample"
step "the report's replay lines ran as printed in the project's folder"

# Every other assignment's README: the same blocks, run as written, but for
# grading (strongest's shows that it works from the project's folder),
# whose line must be the same as strongest's with the name changed.
for other_readme in "$source_dir"/assignments/*/README.md; do
  name=$(basename "$(dirname "$other_readme")")
  [ "$name" != strongest ] || continue
  commands=$(blocks "$other_readme" student)
  if [ -z "$commands" ]; then
    fail "no \`\`\`sh student block in $other_readme"
    continue
  fi
  grep -qx "syrof grade . --assignment $name --public-only" <<<"$commands" ||
    fail "$other_readme: no line 'syrof grade . --assignment $name --public-only'"
  runnable=$(grep -v '^syrof grade ' <<<"$commands")
  (cd "$work" && PATH=$base_path bash -euo pipefail -c "$search_may_break"$'\n'"$runnable") > "$work/$name.log" 2>&1 ||
    { fail "$other_readme: a command failed"; tail -15 "$work/$name.log" >&2; }
  [ -s "$HOME/$name/out/replay.html" ] || fail "$other_readme: no out/replay.html in ~/$name"
done
step "every assignment's README: copy, build, run, view as written"

# The page in a browser: a screenshot of it.
if [ -z "$chromium" ] || [ ! -x "$chromium" ]; then
  fail "no Chromium to open the replay's page ('$chromium')"
else
  shot="$work/replay.png"
  timeout 60 "$chromium" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
    --user-data-dir="$work/chromium" --window-size=1280,900 --virtual-time-budget=3000 \
    --screenshot="$shot" "file://$project/out/replay.html" > "$work/chromium.log" 2>&1
  if [ -s "$shot" ]; then
    step "screenshot of out/replay.html: $(stat -c %s "$shot") bytes"
  else
    fail "Chromium took no screenshot of out/replay.html"
    tail -5 "$work/chromium.log" >&2
  fi
fi

# 2. The instructor.
doc="$source_dir/docs/grading.md"
instructor=$(blocks "$doc" instructor)
[ -n "$instructor" ] || fail "no \`\`\`sh instructor block in $doc"
mkdir -p "$work/instructor"
step "the instructor, from $doc:"
echo "$instructor"
echo "---"
(cd "$work/instructor" && PATH="$bin_dir:$base_path" bash -euo pipefail -c "$instructor") ||
  fail "an instructor command failed (above)"
echo "---"
# The skeleton's README, for its students: its blocks as written, the
# assignment's folder being the one just written (its `/path/to/NAME`).
skeleton_readme="$work/instructor/my_task/README.md"
skeleton=$(blocks "$skeleton_readme" student | sed "s|/path/to/my_task|$work/instructor/my_task|g")
if [ -z "$skeleton" ]; then
  fail "no \`\`\`sh student block in the skeleton's README.md"
else
  (cd "$work" && PATH="$bin_dir:$base_path" bash -euo pipefail -c "$skeleton") > "$work/skeleton.log" 2>&1 ||
    { fail "a command of the skeleton's README failed"; tail -15 "$work/skeleton.log" >&2; }
  [ -s "$HOME/my_task/out/replay.html" ] || fail "the skeleton's README left no out/replay.html"
  mapfile -t skeleton_reports < <(find "$HOME/my_task/grade-out" -name report.html 2>/dev/null)
  [ "${#skeleton_reports[@]}" -gt 0 ] || fail "the skeleton README's syrof grade wrote no report.html"
  step "the skeleton's README ran as written"
fi

graded="$work/instructor/graded"
[ "$(grep -c . "$graded/class.csv" 2>/dev/null)" = 4 ] || fail "class.csv does not hold a header and 3 students"
grep -q '^cyd,0' "$graded/class.csv" 2>/dev/null || fail "class.csv: cyd's code does not compile, yet: $(grep '^cyd' "$graded/class.csv")"
if ! grep -q '^ada,100' "$graded/class.csv" 2>/dev/null; then
  fail "class.csv: ada handed in the reference, yet: $(grep '^ada' "$graded/class.csv")"
  grep -o '"reason": "[^"]\+' "$graded/ada/results.json" | head -5 >&2
fi

# 3. What students are handed: the class's reports in the student's form.
hidden_scenario="$work/instructor/my_task/hidden/spread_8_loss.yaml"
for student in ada bob cyd; do
  report="$graded/$student/report.html"
  if [ ! -s "$report" ]; then
    fail "$student has no report.html"
    continue
  fi
  no_absolute_paths "$report"
  # The hidden run: its name, points and verdict only, not its scenario
  # (file, robots, why they failed) nor its replay.
  for needle in "hidden/spread_8_loss.yaml" "runs/spread_8_loss" "$(sed -n 's/^# \(.*\)/\1/p' "$hidden_scenario" | head -1)"; do
    [ -n "$needle" ] || continue
    if grep -qF -- "$needle" "$report"; then fail "$student's report.html shows the hidden scenario: '$needle'"; fi
  done
done

step "took $(($(date +%s) - started)) s"
if [ "${#failures[@]}" -gt 0 ]; then
  echo "walkthrough: ${#failures[@]} check(s) failed:" >&2
  printf '  - %s\n' "${failures[@]}" >&2
  exit 1
fi
echo "walkthrough: every command of the docs ran and every check passed"
