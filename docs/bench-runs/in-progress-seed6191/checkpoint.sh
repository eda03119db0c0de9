#!/usr/bin/env bash
# Every 15 min: copy the store's complete lines into main's in-progress folder and commit
# (amending the last commit if it is itself a checkpoint).
seed=${1:?seed}; store=${2:?store}; main=/work/main
dir=$main/docs/bench-runs/in-progress-seed$seed
while true; do
  sleep 900
  n=$(grep -c '}$' "$store")
  cd "$main" || exit 1
  head -n "$n" "$store" > "$dir/gap_$seed.jsonl.tmp" && mv "$dir/gap_$seed.jsonl.tmp" "$dir/gap_$seed.jsonl"
  git add "$dir/gap_$seed.jsonl"
  git diff --cached --quiet && continue
  last=$(git log -1 --format=%s)
  msg="bench-runs: checkpoint of the seed-$seed store ($((n - 1)) of 330 cases)"
  if [[ "$last" == "bench-runs: checkpoint of the seed-$seed store"* ]]; then
    git commit -q --amend -m "$msg" -- "$dir/gap_$seed.jsonl"
  else
    git commit -q -m "$msg" -- "$dir/gap_$seed.jsonl"
  fi
done
