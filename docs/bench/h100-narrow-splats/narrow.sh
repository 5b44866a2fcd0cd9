# The portable renderer's far field in 32-bit splat cells against 64-bit cells and against geometry
# (regression set and shipped table), the Vulkan renderer against the commit before (3b0b1f2),
# cis565 2^24's visible blades by blade occluders on both renderers, md5 twice (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; xz -dc .devc/sward-old.xz > /tmp/so; chmod +x /tmp/sn /tmp/so
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/log.txt
t0=$(date +%s)
step() { echo "$1 $(( $(date +%s) - t0 )) s" >> $OUT/log.txt; }
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
S="--shipped --warmup 40 --frames 100 --max-seconds 2"
C="--presets cis565 --counts 16777216 --modes all --warmup 40 --frames 60 --max-seconds 2 --quality high"
mkdir -p /tmp/s
for run in "so:vold:$V" "sn:vnew:$V" "sn:pwide:$V --renderer wgpu" "sn:pnarrow:$V --renderer wgpu --narrow-splats" \
  "sn:pdrawn:$V --renderer wgpu --without int64-atomics,narrow-splats" "sn:swide:$S --renderer wgpu" \
  "sn:snarrow:$S --renderer wgpu --narrow-splats" "sn:sdrawn:$S --renderer wgpu --without int64-atomics,narrow-splats" \
  "sn:cv0:$C --set cull.blade_occluders=0" "sn:cp0:$C --set cull.blade_occluders=0 --renderer wgpu" \
  "sn:cv2:$C --set cull.blade_occluders=262144" "sn:cp2:$C --set cull.blade_occluders=262144 --renderer wgpu"; do
  bin=${run%%:*}; rest=${run#*:}; name=${rest%%:*}; args=${rest#*:}
  timeout 120 /tmp/$bin bench $args --out /tmp/$name > /tmp/s/$name.log 2>&1
  cp /tmp/$name/summary.csv /tmp/s/$name-summary.csv; step $name
  tar -C /tmp/s -cf $OUT/summaries.tar .
done
for s in trample trail landscape prairie; do for i in 1 2; do
  timeout 60 /tmp/sn render --narrow-splats --scene $s --renderer wgpu --width 1920 --height 1080 --steps 60 --out /tmp/$s-$i.png > /dev/null 2>/tmp/s/$s-$i.err
  echo "$s wgpu narrow $i $(md5sum < /tmp/$s-$i.png | cut -c1-12)" >> $OUT/log.txt
done; done
cp /tmp/landscape-1.png $OUT/landscape-narrow.png
/tmp/sn render --scene landscape --renderer wgpu --width 1920 --height 1080 --steps 60 --out $OUT/landscape-wide.png > /dev/null 2>&1
step md5
tar -C /tmp/s -cf $OUT/summaries.tar .
cat $OUT/log.txt
