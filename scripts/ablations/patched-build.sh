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
