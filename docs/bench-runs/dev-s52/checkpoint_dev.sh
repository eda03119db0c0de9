#!/usr/bin/env bash
# Every 15 min: copy a development bench store's complete lines into this folder and commit them to main
# (amending the last commit if it is itself this store's checkpoint). Usage: checkpoint_dev.sh STORE NAME
store=${1:?store}; name=${2:?name}; main=/work/main
dir=$main/docs/bench-runs/dev-s52
while true; do
  sleep 900
  n=$(grep -c '}$' "$store")
  cd "$main" || exit 1
  head -n "$n" "$store" > "$dir/$name.tmp" && mv "$dir/$name.tmp" "$dir/$name"
  git add "$dir/$name"
  git diff --cached --quiet && continue
  last=$(git log -1 --format=%s)
  msg="dev-s52: checkpoint of the development store $name ($((n - 1)) of 330 cases)"
  if [[ "$last" == "dev-s52: checkpoint of the development store $name"* ]]; then
    git commit -q --amend -m "$msg" -- "$dir/$name"
  else
    git commit -q -m "$msg" -- "$dir/$name"
  fi
done
