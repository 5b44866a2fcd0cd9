# Both renderers' regression sets, old then new, and the portable renderer's bytes twice (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; xz -dc .devc/sward-old.xz > /tmp/so; chmod +x /tmp/sn /tmp/so
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
/tmp/so bench $V --out $OUT/vold > /dev/null 2>&1
/tmp/sn bench $V --out $OUT/vnew > /dev/null 2>&1
/tmp/sn bench --compare $OUT/vold $OUT/vnew > $OUT/vulkan-compare.txt 2>&1; echo "rc=$?" >> $OUT/vulkan-compare.txt
P="--renderer wgpu --regression-set --warmup 30 --frames 60 --max-seconds 2 --quality high"
/tmp/sn bench $P --out $OUT/pnew > /dev/null 2>&1
/tmp/so bench $P --out $OUT/pold > /dev/null 2>&1
/tmp/sn bench --compare $OUT/pold $OUT/pnew > $OUT/portable-compare.txt 2>&1; echo "rc=$?" >> $OUT/portable-compare.txt
for s in prairie trample; do for i in 1 2; do
  timeout 60 /tmp/sn render --scene $s --renderer wgpu --width 1920 --height 1080 --steps 60 --out /tmp/$s-$i.png > /dev/null 2>&1
  echo "$s wgpu $i $(md5sum < /tmp/$s-$i.png | cut -c1-12)" >> $OUT/md5.txt
done; done
for d in vold vnew pold pnew; do cp $OUT/$d/summary.csv $OUT/$d-summary.csv; rm -rf $OUT/$d; done
cat $OUT/vulkan-compare.txt $OUT/portable-compare.txt $OUT/md5.txt
