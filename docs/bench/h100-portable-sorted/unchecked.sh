# The portable renderer without WebGPU's checks and with the kept ground copied only where needed:
# both renderers' regression sets and shipped tables, the portable one also with the checks (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; chmod +x /tmp/sn
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
t0=$(date +%s)
step() { echo "$1 $(( $(date +%s) - t0 )) s" >> $OUT/steps.txt; }
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
S="--shipped --warmup 40 --frames 100 --max-seconds 2"
/tmp/sn bench $V --out /tmp/vnew > /dev/null 2>&1; cp /tmp/vnew/summary.csv $OUT/vnew-summary.csv; step vnew
/tmp/sn bench $V --renderer wgpu --out /tmp/pnew > /dev/null 2>&1; cp /tmp/pnew/summary.csv $OUT/pnew-summary.csv; step pnew
/tmp/sn bench $S --out /tmp/vship > /dev/null 2>&1; cp /tmp/vship/summary.csv $OUT/vship-summary.csv; step vship
/tmp/sn bench $S --renderer wgpu --out /tmp/pship > /dev/null 2>&1; cp /tmp/pship/summary.csv $OUT/pship-summary.csv; step pship
/tmp/sn bench $V --renderer wgpu --wgsl-checks --out /tmp/pchk > /dev/null 2>&1; cp /tmp/pchk/summary.csv $OUT/pchecked-summary.csv; step pchecked
mkdir -p $OUT/det
for s in trample trail landscape prairie; do
  for i in 1 2; do
    timeout 60 /tmp/sn render --scene $s --renderer wgpu --width 1920 --height 1080 --steps 60 --out /tmp/$s-$i.png > /dev/null 2>$OUT/det/$s-$i.err
    echo "$s wgpu $i $(md5sum < /tmp/$s-$i.png | cut -c1-12)" >> $OUT/det/md5.txt
  done
done
step md5
cat $OUT/steps.txt $OUT/det/md5.txt
