# The Vulkan renderer's regression set: new, old, new (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; xz -dc .devc/sward-old.xz > /tmp/so; chmod +x /tmp/sn /tmp/so
B="--regression-set --warmup 40 --frames 100 --max-seconds 2.5 --quality high"
/tmp/sn bench $B --out $OUT/new1 > $OUT/new1.log 2>&1
/tmp/so bench $B --out $OUT/old > $OUT/old.log 2>&1
/tmp/sn bench $B --out $OUT/new2 > $OUT/new2.log 2>&1
/tmp/sn bench --compare $OUT/old $OUT/new1 > $OUT/compare1.txt 2>&1; echo "rc1=$?" >> $OUT/compare1.txt
/tmp/sn bench --compare $OUT/old $OUT/new2 > $OUT/compare2.txt 2>&1; echo "rc2=$?" >> $OUT/compare2.txt
cat $OUT/compare1.txt $OUT/compare2.txt
