# Sourced by the benchmark scripts: the masonry-hpc binary of an earlier commit, to time it beside
# the current one in the same run ("old and new binary, side by side").
#
#   baseline_binary <commit>   prints the path of that commit's release binary, building it first
#                              when missing (a detached git worktree under target/baseline/src-<sha>,
#                              its own target folder target/baseline/<sha>; about 5 min on 2 cores)
baseline_binary() {
  local commit sha dir
  commit=$1
  sha=$(git rev-parse --short=12 "$commit^{commit}") || { echo "error: BASELINE=$commit is not a commit" >&2; return 2; }
  dir=$PWD/target/baseline
  if [ ! -x "$dir/$sha/release/masonry-hpc" ]; then
    echo "building the baseline masonry-hpc at $sha (once; kept in target/baseline/$sha)" >&2
    mkdir -p "$dir"
    [ -d "$dir/src-$sha" ] || git worktree add --detach "$dir/src-$sha" "$sha" >&2
    (cd "$dir/src-$sha" && CARGO_TARGET_DIR="$dir/$sha" cargo build --release --quiet >&2)
    git worktree remove --force "$dir/src-$sha" >&2 || true
  fi
  echo "$dir/$sha/release/masonry-hpc"
}
