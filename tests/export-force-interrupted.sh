#!/bin/sh
# pkm export linuxcnc --force stopped by SIGTERM at any moment leaves one whole configuration:
# the old one or the new one, its INI's PKM_MACHINE_SHA256 that of the machine file beside it,
# the user's file still there, and nothing beside the directory.
# Usage: export-force-interrupted.sh PKM MACHINE.toml WORK_DIRECTORY
set -u
pkm=$1 machine=$2 dir=$3
rm -rf "$dir" && mkdir -p "$dir/parent" || exit 1
cfg=$dir/parent/cfg
fail() { echo "FAIL (run $run): $*"; ls -laR "$dir/parent"; exit 1; }
mkdir -p "$dir/a" "$dir/b" && cp "$machine" "$dir/a/m.toml" && cp "$machine" "$dir/b/m.toml" &&
  echo '# b' >>"$dir/b/m.toml" || exit 1
"$pkm" export linuxcnc -m "$dir/a/m.toml" -o "$cfg" --sim >/dev/null || exit 1
echo 'net mine' >"$cfg/mine.hal"
run=0 replaced=0
# Delays from 0 to 0.12 s (an export takes about 0.1 s): before, during and after the joint-rate
# bound, the writing and the swap.
for delay in $(seq 0 0.005 0.12); do
  run=$((run + 1))
  from=$([ $((run % 2)) -eq 0 ] && echo a || echo b)
  "$pkm" export linuxcnc -m "$dir/$from/m.toml" -o "$cfg" --sim --force >/dev/null 2>&1 &
  pid=$!
  sleep "$delay"
  kill -TERM $pid 2>/dev/null
  wait $pid
  [ "$(ls -A "$dir/parent")" = cfg ] || fail "left beside the configuration: $(ls -A "$dir/parent")"
  [ "$(ls "$cfg" | xargs)" = "m.hal m.ini m.tbl m.toml m.var mine.hal sim.hal" ] ||
    fail "not one whole configuration: $(ls "$cfg" | xargs)"
  recorded=$(sed -n 's/^PKM_MACHINE_SHA256 = //p' "$cfg/m.ini")
  [ "$recorded" = "$(sha256sum "$cfg/m.toml" | cut -d' ' -f1)" ] ||
    fail "the INI's machine file SHA-256 is not that of the file beside it"
  [ "$(cat "$cfg/mine.hal")" = 'net mine' ] || fail "the user's file changed"
  cmp -s "$cfg/m.toml" "$dir/$from/m.toml" && replaced=$((replaced + 1))
done
echo "$run exports stopped by SIGTERM ($replaced of them after the swap), each leaving one whole configuration"
