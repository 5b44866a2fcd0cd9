# The portable renderer's determinism and its regression set, new against old (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; xz -dc .devc/sward-old.xz > /tmp/so; chmod +x /tmp/sn /tmp/so
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
mkdir -p $OUT/det
for s in trample trail landscape prairie meadow; do
  for r in wgpu vulkan; do
    for i in 1 2; do
      timeout 60 /tmp/sn render --scene $s --renderer $r --width 1920 --height 1080 --steps 60 --out /tmp/$s-$r-$i.png > /dev/null 2>$OUT/det/$s-$r-$i.err
      echo "$s $r $i $(md5sum < /tmp/$s-$r-$i.png | cut -c1-12)" >> $OUT/det/md5.txt
    done
  done
done
cp /tmp/prairie-wgpu-1.png /tmp/trample-wgpu-1.png $OUT/det/ 2>/dev/null
B="--renderer wgpu --regression-set --warmup 30 --frames 60 --max-seconds 2 --quality high"
/tmp/sn bench $B --out $OUT/pnew > $OUT/pnew.log 2>&1
/tmp/so bench $B --out $OUT/pold > $OUT/pold.log 2>&1
/tmp/sn bench --compare $OUT/pold $OUT/pnew --tolerance 3 > $OUT/pcompare.txt 2>&1
cat $OUT/det/md5.txt $OUT/pcompare.txt
