# Both renderers' regression sets in one call: this change's binary (sn) and 38b8de3's (so).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; xz -dc .devc/sward-old.xz > /tmp/so; chmod +x /tmp/sn /tmp/so
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
/tmp/sn bench $V --out $OUT/vnew > /dev/null 2>&1
/tmp/so bench $V --out $OUT/vold > /dev/null 2>&1
/tmp/sn bench --compare $OUT/vold $OUT/vnew > $OUT/vulkan-compare.txt 2>&1; echo "rc=$?" >> $OUT/vulkan-compare.txt
P="--renderer wgpu --regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
/tmp/sn bench $P --out $OUT/pnew > /dev/null 2>&1
/tmp/so bench $P --out $OUT/pold > /dev/null 2>&1
/tmp/sn bench --compare $OUT/pold $OUT/pnew > $OUT/portable-compare.txt 2>&1; echo "rc=$?" >> $OUT/portable-compare.txt
for d in vold vnew pold pnew; do cp $OUT/$d/summary.csv $OUT/$d-summary.csv; cp $OUT/$d/memory.csv $OUT/$d-memory.csv 2>/dev/null; rm -rf $OUT/$d; done
cat $OUT/vulkan-compare.txt $OUT/portable-compare.txt
