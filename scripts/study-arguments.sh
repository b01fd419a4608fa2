# Sourced by the study scripts (read_noise_study.sh, restoration_study.sh,
# velocity_robustness.sh): `study_arguments NAME "$@"` parses their common
# command line, [--update-docs] [OUT_DIR] or -h, and sets root (the checkout),
# update_docs (0 or 1), out (OUT_DIR, default out/NAME, absolute) and fssim
# (FSSIM, default build/fssim, absolute). -h prints the script's header
# comment; a usage error exits 2, naming the script.
study_arguments() {
  local name=$1 argument
  shift
  root=$(cd "$(dirname "$0")/.." && pwd)
  update_docs=0
  out=""
  for argument in "$@"; do
    case "$argument" in
      --update-docs) update_docs=1 ;;
      -h | --help)
        sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
        exit 0
        ;;
      -*)
        echo "$name: unknown option $argument (usage: $0 [--update-docs] [OUT_DIR])" >&2
        exit 2
        ;;
      *)
        [ -z "$out" ] || { echo "$name: one OUT_DIR only" >&2; exit 2; }
        out=$argument
        ;;
    esac
  done
  out=$(realpath -m "${out:-$root/out/$name}")
  fssim=$(realpath -m "${FSSIM:-$root/build/fssim}")
}
