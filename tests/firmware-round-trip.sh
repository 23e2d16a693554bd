#!/bin/sh
# pkm export TARGET of a machine, pkm import TARGET of that file, pkm export TARGET of the imported
# machine: the settings come back byte for byte (docs/firmware.md). The first line of each file
# names the machine file it came from, so the first generation is compared without it; where a
# target's comments name the machine's joints (an imported machine names them after the
# firmware's towers), JOINT_COMMENTS is an extended regex for those lines, left out too. Then
# once more from the imported file, every name the same: the whole text, byte for byte.
# Usage: firmware-round-trip.sh PKM TARGET MACHINE WORK_DIRECTORY [JOINT_COMMENTS]
set -u
pkm=$1 target=$2 machine=$3 dir=$4 joint_comments=${5:-}
rm -rf "$dir" && mkdir -p "$dir" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
export_to() {  # export_to MACHINE OUTPUT
  if [ "$target" = grblhal ]; then
    "$pkm" export grblhal --kinematics -m "$1" -o "$2" >/dev/null
  else
    "$pkm" export "$target" -m "$1" -o "$2" >/dev/null
  fi
}
settings() {  # the file without its first line (and the joint comments)
  if [ -n "$joint_comments" ]; then
    tail -n +2 "$1" | grep -Ev "$joint_comments"
  else
    tail -n +2 "$1"
  fi
}

export_to "$machine" "$dir/exported" || fail "export of $machine"
"$pkm" import "$target" "$dir/exported" -o "$dir/imported.toml" >/dev/null 2>&1 ||
  fail "import of the exported file"
export_to "$dir/imported.toml" "$dir/again" 2>/dev/null || fail "export of the imported machine"
settings "$dir/exported" >"$dir/exported.settings"
settings "$dir/again" >"$dir/again.settings"
[ -s "$dir/exported.settings" ] || fail "nothing exported"
cmp "$dir/exported.settings" "$dir/again.settings" ||
  { diff "$dir/exported.settings" "$dir/again.settings"; fail "the settings differ"; }

mv "$dir/again" "$dir/exported"
"$pkm" import "$target" "$dir/exported" -o "$dir/imported.toml" >/dev/null 2>&1 ||
  fail "second import"
export_to "$dir/imported.toml" "$dir/again" 2>/dev/null || fail "second export"
cmp "$dir/exported" "$dir/again" || { diff "$dir/exported" "$dir/again"; fail "the texts differ"; }
echo "round trip: $(grep -cv '^$' "$dir/exported") lines, the same text"
