# shellcheck shell=bash
# Sourced by the ablation scripts that measure an idea the code does not keep (not run): a
# commit, with one of this folder's patches or as it is, checked out in a worktree and its
# shadowbench built there. `build_at NAME COMMIT [PATCH]` leaves the binary at
# "$work/NAME-build/harness/shadowbench"; the worktrees and $work go when the script exits.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(git -C "$here" rev-parse --show-toplevel)
work=$(mktemp -d)
worktrees=()
remove_worktrees() {
  local tree
  for tree in "${worktrees[@]}"; do git -C "$repo" worktree remove --force "$tree" 2>/dev/null; done
  rm -rf "$work"
}
trap remove_worktrees EXIT
# shellcheck source=scripts/compiler-cache.sh
source "$repo/scripts/compiler-cache.sh"
export CCACHE_BASEDIR="$work"  # worktrees of one name hit across runs

build_at() {
  local name=$1 commit=$2 patch=${3:-}
  git -C "$repo" worktree add --detach "$work/$name" "$commit" >/dev/null
  worktrees+=("$work/$name")
  [ -z "$patch" ] || git -C "$work/$name" apply "$here/$patch"
  if ! { cmake -S "$work/$name" -B "$work/$name-build" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" &&
    cmake --build "$work/$name-build" --target shadowbench -j"$(nproc)"; } >"$work/$name.log" 2>&1; then
    tail -n 40 "$work/$name.log" >&2
    exit 1
  fi
}

# `alternate_on_cells RESOLUTION NAME...`: on the city, the terrain and the tangle closed, the
# forest static and the city open, one `delta-dag` structure built by the last NAME's build (the
# builds must share its layout), then each NAME's `shadowbench bench --filters 1,9 --rounds 3` on
# it in turn, four times; each line gives uniform 1×1, uniform 9×9, view 1×1 and view 9×9 in ns per
# query (one thread).
alternate_on_cells() {
  local resolution=$1 cell scene mode run name
  shift
  for cell in "city:full closed" "terrain:full closed" "tangle:full closed" "forest:full static" \
    "city:full open"; do
    read -r scene mode <<<"$cell"
    "$work/${*: -1}-build/harness/shadowbench" build --scheme delta-dag -s "$scene" -m "$mode" \
      -r "$resolution" --no-bench --no-verify --results "$work/records" -o "$work/structure.sb" \
      >/dev/null
    for run in 1 2 3 4; do
      for name in "$@"; do
        printf '%s %s %s, run %d, %s: ' "$scene" "$mode" "$resolution" "$run" "$name"
        "$work/$name-build/harness/shadowbench" bench "$work/structure.sb" -s "$scene" \
          --filters 1,9 --rounds 3 | awk '/^(uniform|view)/ { printf "%s ", $4 } END { print "" }'
      done
    done
  done
}
