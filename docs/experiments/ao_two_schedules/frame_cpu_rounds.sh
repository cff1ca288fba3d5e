#!/bin/bash
# More rounds of frame_cpu.sh's raster and hybrid rows (this build against a478cc7, alternating,
# $ROUNDS rounds), then the same with the process pinned to one core (`taskset -c 5`), to see
# whether the spread between processes of one binary is the code or where the process runs.
# One line a run: the name and scene update + uniforms + submit in ms; logs in
# $OUT/frame_cpu_rounds.tgz.
set -u
for f in .gpu/gl/*.deb; do dpkg -x $f / ; done; ldconfig
for b in raygraph raygraph_a478cc7; do xz -dc .gpu/$b.xz > /tmp/$b; chmod +x /tmp/$b; done
OUT=${OUT:-/tmp/out}; mkdir -p $OUT/g /tmp/empty
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
one() { local pin=$1 bin=$2 name=$3; shift 3; local log=$OUT/g/$name.log
  (cd /tmp/empty && timeout 60 $pin /tmp/$bin render --scene atrium --backend compute --width 2560 --height 1440 --frames 60 --out /tmp/x.png "$@" > $log 2>&1) || tail -2 $log
  grep -E '^outside' $log | sed -E "s/.*scene update ([0-9.]+), uniforms ([0-9.]+), submit ([0-9.]+).*/\1 \2 \3/" | awk -v n=$name '{printf "%s %.3f\n", n, $1+$2+$3}'
}
for pin in "" "taskset -c 5"; do
  tag=free; [ -n "$pin" ] && tag=pinned
  for round in $(seq 1 ${ROUNDS:-5}); do
    for mode in raster hybrid; do
      for bin in raygraph raygraph_a478cc7; do
        if [ $SECONDS -gt ${DEADLINE:-300} ]; then echo "deadline"; break 4; fi
        one "$pin" $bin ${tag}_${mode}_${bin}_$round --mode $mode
      done
    done
  done
done
cd $OUT && tar czf frame_cpu_rounds.tgz g && rm -rf g
