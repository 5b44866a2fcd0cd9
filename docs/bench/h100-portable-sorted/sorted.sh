# The portable renderer with its strips' blades sorted by exact distance, without WebGPU's checks, the
# kept ground copied only where needed: both renderers' regression sets and shipped tables, md5 twice (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; chmod +x /tmp/sn
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
t0=$(date +%s)
step() { echo "$1 $(( $(date +%s) - t0 )) s" >> $OUT/steps.txt; }
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
S="--shipped --warmup 40 --frames 100 --max-seconds 2"
for run in "vnew:$V" "pnew:$V --renderer wgpu" "vship:$S" "pship:$S --renderer wgpu"; do
  name=${run%%:*}; args=${run#*:}
  /tmp/sn bench $args --out /tmp/$name > /dev/null 2>&1
  cp /tmp/$name/summary.csv $OUT/$name-summary.csv; step $name
done
for s in trample trail landscape prairie; do
  for i in 1 2; do
    timeout 60 /tmp/sn render --scene $s --renderer wgpu --width 1920 --height 1080 --steps 60 --out /tmp/$s-$i.png > /dev/null 2>/tmp/$s-$i.err
    echo "$s wgpu $i $(md5sum < /tmp/$s-$i.png | cut -c1-12)" >> $OUT/md5.txt
  done
done
step md5
cat $OUT/steps.txt $OUT/md5.txt
