# Sourced by the reproduction scripts (tracker.sh, reproduce.sh, pipelines.sh, main.sh): where they
# write. The CSVs and figures always go to a scratch folder: they are regenerated, so the source
# tree does not keep them. Reproducing a table never edits the documents unless asked.
#   --out DIR       write the CSVs, figures and a copy of RESULTS.md with the regenerated
#                   sections into DIR (default: BUILD_DIR/results)
#   --update-docs   CSVs and figures into BUILD_DIR/results as by default, the regenerated
#                   sections into docs/RESULTS.md itself, and the few figures that docs/figures
#                   keeps copied there
#   --dry-run       print the commands, run nothing
# parse_output_flags ARGS... sets OUT_ROOT, FIGURES, RESULTS_MD, UPDATE_DOCS, DRY_RUN and REST (the
# other arguments, in order); BUILD_DIR must be set first when --out is not given, or call
# resolve_output_folder after setting it.
parse_output_flags() {
  OUT_ROOT="" UPDATE_DOCS=0 DRY_RUN=0 REST=()
  while [ $# -gt 0 ]; do
    case "$1" in
      --out)
        [ $# -ge 2 ] && [ -n "$2" ] || { echo "$(basename "$0"): --out needs a folder" >&2; exit 2; }
        OUT_ROOT=$2
        shift 2 ;;
      --update-docs) UPDATE_DOCS=1; shift ;;
      --dry-run) DRY_RUN=1; shift ;;
      *) REST+=("$1"); shift ;;
    esac
  done
  if [ "$UPDATE_DOCS" = 1 ] && [ -n "$OUT_ROOT" ]; then
    echo "$(basename "$0"): --out and --update-docs exclude each other" >&2
    exit 2
  fi
}

# Sets OUT_ROOT (CSVs), FIGURES and RESULTS_MD from the flags and BUILD_DIR. Without
# --update-docs the regenerated sections go into a copy of docs/RESULTS.md, to compare with `diff`.
resolve_output_folder() {
  if [ "$UPDATE_DOCS" = 1 ]; then
    OUT_ROOT=$BUILD_DIR/results FIGURES=$BUILD_DIR/results/figures RESULTS_MD=docs/RESULTS.md
    run mkdir -p "$OUT_ROOT"
    return
  fi
  OUT_ROOT=${OUT_ROOT:-$BUILD_DIR/results}
  FIGURES=$OUT_ROOT/figures RESULTS_MD=$OUT_ROOT/RESULTS.md
  case "$(realpath -m "$OUT_ROOT")/" in
    "$(realpath -m docs)"/*)
      echo "$(basename "$0"): $OUT_ROOT is inside docs/: use --update-docs to change the documents" >&2
      exit 2 ;;
  esac
  run mkdir -p "$OUT_ROOT"
  if [ ! -f "$RESULTS_MD" ]; then run cp docs/RESULTS.md "$RESULTS_MD"; fi
}

# Runs (or, under --dry-run, prints on stderr: some callers capture stdout) one command.
run() {
  if [ "$DRY_RUN" = 1 ]; then
    { printf '+'; printf ' %q' "$@"; printf '\n'; } >&2
  else
    "$@"
  fi
}

# Under --update-docs, the figures that docs/figures keeps are replaced by the new ones of the
# same name; the others stay in FIGURES. The README's view strip is a reduced copy (a photo
# strip at full size is 0.3 MB), so it is not replaced.
copy_doc_figures() {
  local kept
  for kept in docs/figures/*.png; do
    case "$kept" in *_views.png) continue ;; esac
    if [ -f "$FIGURES/$(basename "$kept")" ]; then run cp "$FIGURES/$(basename "$kept")" "$kept"; fi
  done
}

# The closing line: where the outputs are.
report_output_folder() {
  if [ "$UPDATE_DOCS" = 1 ]; then
    copy_doc_figures
    echo "$(basename "$0"): CSVs and figures in $OUT_ROOT; updated docs/RESULTS.md's generated sections and the figures docs/figures keeps"
  else
    echo "$(basename "$0"): outputs in $OUT_ROOT (compare: diff docs/RESULTS.md $RESULTS_MD; --update-docs writes docs/)"
  fi
}
