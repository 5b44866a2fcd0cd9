# This change's binary: both renderers' regression sets and shipped tables, and the portable
# renderer's bytes twice at 1920x1080 (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; chmod +x /tmp/sn
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
/tmp/sn bench $V --out $OUT/vnew > /dev/null 2>&1
/tmp/sn bench $V --renderer wgpu --out $OUT/pnew > /dev/null 2>&1
S="--shipped --warmup 40 --frames 100 --max-seconds 2"
/tmp/sn bench $S --out $OUT/vship > /dev/null 2>&1
/tmp/sn bench $S --renderer wgpu --out $OUT/pship > /dev/null 2>&1
for s in trample trail landscape prairie; do for i in 1 2; do
  timeout 60 /tmp/sn render --scene $s --renderer wgpu --width 1920 --height 1080 --steps 30 --out /tmp/$s-$i.png > /dev/null 2>&1
  echo "$s wgpu $i $(md5sum < /tmp/$s-$i.png | cut -c1-12)" >> $OUT/md5.txt
done; done
for d in vnew pnew vship pship; do cp $OUT/$d/summary.csv $OUT/$d-summary.csv; rm -rf $OUT/$d; done
cat $OUT/md5.txt
