# The kept shadow ground: both renderers' regression sets and shipped tables (one call).
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
for d in vnew pnew vship pship; do cp $OUT/$d/summary.csv $OUT/$d-summary.csv; rm -rf $OUT/$d; done
ls $OUT
