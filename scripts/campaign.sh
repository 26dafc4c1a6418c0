#!/usr/bin/env bash
# Keeps a long validation run (docs/validation.md) going across machines. A run of the seed's 8 s takes longer than
# one sitting, and bench/ (where scripts/validate.sh writes) is not in git, so a fresh checkout has lost it. `save`
# packs the run's newest checkpoint (xz) and its small records (monitor.csv, command.txt, stdout.txt, machine.txt,
# summary.json, and analysis.h5 once a finished run has written its averages there) into campaign/<name>/, which is
# committed; `restore` unpacks them into the run folder, after which the run continues with FLUIDBED_CONTINUE=1 and
# its usual command. The checkpoint holds the time averages as well,
# so averages begun before a save go on after the restore. Snapshots are not kept (they are redrawn from a rerun).
#   scripts/campaign.sh save    <run folder> <name>     e.g. bench/spouted550_kn150/spouted_550_jet1_u160 spouted_550_kn150
#   scripts/campaign.sh restore <name> <run folder>
#   scripts/campaign.sh list
# FLUIDBED_CAMPAIGN_DIR stores elsewhere than campaign/ (the tests do).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
store=${FLUIDBED_CAMPAIGN_DIR:-$root/campaign}
records=(monitor.csv command.txt stdout.txt machine.txt summary.json analysis.h5)
usage() { sed -n '2,12p' "$0" >&2; exit 2; }
[[ $# -ge 1 ]] || usage

# The run's bed time and step at its checkpoint, read from the checkpoint itself.
checkpoint_time() {
  /usr/bin/python3 - "$1" <<'EOF'
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    a = f.attrs
    print(f"t = {a['time']:.6g} s, step {int(a['step'])}" if "time" in a and "step" in a else "unknown")
EOF
}

case $1 in
save)
  [[ $# -eq 3 ]] || usage
  run=$2 name=$3
  [[ -f $run/checkpoint.h5 ]] || { echo "campaign.sh: $run has no checkpoint.h5 to save" >&2; exit 2; }
  mkdir -p "$store/$name"
  # A running job replaces checkpoint.h5 by a rename: a hard link holds the file of this moment for the packing, the
  # hash and the time below (monitor.csv may run ahead of it; a restart drops the rows after the checkpoint's step).
  held=$run/.campaign_checkpoint.h5
  ln -f "$run/checkpoint.h5" "$held" 2>/dev/null || cp "$run/checkpoint.h5" "$held"
  trap 'rm -f "$held"' EXIT
  # Pack to a temporary name first: a stop half-way must not leave a truncated checkpoint where a good one was.
  xz -T1 -6 -c "$held" >"$store/$name/checkpoint.h5.xz.part"
  mv "$store/$name/checkpoint.h5.xz.part" "$store/$name/checkpoint.h5.xz"
  for r in "${records[@]}"; do
    # the averages only from a run that ended at its -t_final (summary.json's exit code 0): a running or interrupted
    # run's analysis.h5 is redrawn from its checkpoint, and would only add megabytes to every save
    [[ $r == analysis.h5 ]] && ! grep -q '"exit_code": 0' "$run/summary.json" 2>/dev/null && continue
    [[ -f $run/$r ]] && cp "$run/$r" "$store/$name/$r"
  done
  {
    echo "checkpoint: $(checkpoint_time "$held")"
    echo "saved: $(date -u +%Y-%m-%dT%H:%M:%SZ) from $run, fluidbed $(git -C "$root" rev-parse --short HEAD)"
    echo "sha256: $(sha256sum "$held" | cut -d' ' -f1)"
  } >"$store/$name/state.txt"
  echo "campaign.sh: saved $run to $store/$name ($(du -h "$store/$name/checkpoint.h5.xz" | cut -f1)); commit it"
  cat "$store/$name/state.txt"
  ;;
restore)
  [[ $# -eq 3 ]] || usage
  name=$2 run=$3
  [[ -f $store/$name/checkpoint.h5.xz ]] || { echo "campaign.sh: no saved run campaign/$name" >&2; exit 2; }
  if [[ -f $run/checkpoint.h5 ]]; then
    echo "campaign.sh: $run already has a checkpoint.h5; move it away first (restore does not overwrite a run)" >&2
    exit 2
  fi
  mkdir -p "$run/plots"
  # a pack that does not unpack to the saved file leaves nothing behind
  refuse() {
    rm -f "$run/checkpoint.h5.part"
    echo "campaign.sh: campaign/$name/checkpoint.h5.xz $1" >&2
    exit 1
  }
  xz -d -c "$store/$name/checkpoint.h5.xz" >"$run/checkpoint.h5.part" || refuse "does not unpack (damaged)"
  want=$(sed -n 's/^sha256: //p' "$store/$name/state.txt")
  got=$(sha256sum "$run/checkpoint.h5.part" | cut -d' ' -f1)
  [[ -z $want || $want == "$got" ]] || refuse "unpacks to a different file (sha256 $got, saved $want)"
  mv "$run/checkpoint.h5.part" "$run/checkpoint.h5"
  for r in "${records[@]}"; do
    [[ -f $store/$name/$r ]] && cp "$store/$name/$r" "$run/$r"
  done
  echo "campaign.sh: restored campaign/$name into $run; continue it with FLUIDBED_CONTINUE=1 and its command:"
  tail -n 1 "$run/command.txt" 2>/dev/null || true
  ;;
list)
  for d in "$store"/*/; do
    [[ -f $d/state.txt ]] && echo "$(basename "$d"): $(head -n 1 "$d/state.txt")"
  done
  ;;
*) usage ;;
esac
