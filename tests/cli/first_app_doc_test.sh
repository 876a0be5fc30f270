#!/usr/bin/env bash
# docs/apps.md, "Your first app", run as written: every ```sh block of the
# section, in order, in one shell, in a fresh folder outside the source
# tree, with PATH starting at the build tree's bin/ (what the section's
# ```sh from-a-clone block sets up; that block's `make build` is what built
# this tree, so it is checked, not run). The doc cannot drift from what works.
#   first_app_doc_test.sh SOURCE_DIR BIN_DIR
set -euo pipefail
source_dir=$1
bin_dir=$2
doc="$source_dir/docs/apps.md"

# The section: from its heading to the next level-2 heading.
section=$(awk '/^## Your first app$/ {on = 1; next} on && /^## / {exit} on {print}' "$doc")
[ -n "$section" ] || { echo "no '## Your first app' section in $doc" >&2; exit 1; }

# The set-up block must say what this test stands in for.
setup=$(awk '/^```sh from-a-clone$/ {on = 1; next} on && /^```$/ {exit} on {print}' <<<"$section")
grep -qx 'make build' <<<"$setup" || { echo "the from-a-clone block lost 'make build'" >&2; exit 1; }
grep -qx 'export PATH="$PWD/build/bin:$PATH"' <<<"$setup" || { echo "the from-a-clone block lost the PATH line" >&2; exit 1; }

# The commands: every ```sh block (not from-a-clone), in order.
commands=$(awk '/^```sh$/ {on = 1; next} on && /^```$/ {on = 0; next} on {print}' <<<"$section")
[ -n "$commands" ] || { echo "no \`\`\`sh block in the section" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "running in $work:"
echo "$commands"
echo "---"
cd "$work"
PATH="$bin_dir:$PATH" bash -euo pipefail -c "$commands"
echo "---"
# Where the section says the outputs are.
for file in myapp/out/myapp/metrics.json myapp/out/myapp/replay myapp/out/myapp/robots/0.log myapp/build/libmyapp.so; do
  [ -s "$file" ] || { echo "$file is missing or empty" >&2; exit 1; }
done
echo "first_app_doc_test: every command of the section ran"
