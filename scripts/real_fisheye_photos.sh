# Sourced by reproduce.sh and pipelines.sh, after scripts/output_folder.sh (for `run`): the real
# fisheye photos of ../shared with their calibrations (eval/eval_datasets.hpp kTurnedLensPhotos
# lists the same three, for the tracker benchmark and the held-out list). export_real_fisheye_views EVAL DATA DIR writes each one,
# seen again by the same lens turned (mdbrief-eval export-rotated-views: exact ground truth, the
# rotations), into DIR/<name>/ (img1..6.png, camera.yaml, H1to2..6) and prints the names it wrote, one per line.
export_real_fisheye_views() {
  local eval=$1 data=$2 dir=$3 name image camera
  if [ ! -d "$data/fisheye" ]; then
    echo "skipping the real fisheye photos: $data/fisheye not found" >&2
    return 0
  fi
  while read -r name image camera; do
    if [ ! -f "$data/fisheye/$image" ]; then
      echo "skipping $name: $data/fisheye/$image not found" >&2
      continue
    fi
    run "$eval" export-rotated-views --image "$data/fisheye/$image" --camera "$data/fisheye/$camera" \
      --out "$dir/$name" >&2
    echo "$name"
  done <<'EOF_PHOTOS'
ocamcalib_sample ocamcalib-sample/test_fisheye.jpg ocamcalib-sample/calib_results.txt
calib_adapter_kb calib-adapter/kalibr/image.png calib-adapter/kalibr/KB.yml
calib_adapter_ocam calib-adapter/OcamCalib/image.jpg calib-adapter/OcamCalib/OcamCalib.yml
EOF_PHOTOS
}

# The flags that evaluate DIR/<name> as user data.
user_sequence_flags() {
  local seq=$1
  echo --user-images "$seq"/img{1..6}.png --user-camera "$seq/camera.yaml" --user-homographies "$seq"/H1to{2..6}
}
