# Both renderers' shipped tables (this change's binary), and each renderer's bytes twice at 1920x1080.
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; chmod +x /tmp/sn
S="--shipped --warmup 40 --frames 100 --max-seconds 2"
/tmp/sn bench $S --out $OUT/vship > /dev/null 2>&1
/tmp/sn bench $S --renderer wgpu --out $OUT/pship > /dev/null 2>&1
for s in trample trail landscape prairie; do for r in vulkan wgpu; do for i in 1 2; do
  timeout 60 /tmp/sn render --scene $s --renderer $r --width 1920 --height 1080 --steps 30 --out /tmp/$s-$r-$i.png > /dev/null 2>&1
  echo "$s $r $i $(md5sum < /tmp/$s-$r-$i.png | cut -c1-12)" >> $OUT/md5.txt
done; done; done
cp /tmp/landscape-wgpu-1.png $OUT/landscape-portable.png; cp /tmp/landscape-vulkan-1.png $OUT/landscape-vulkan.png
for d in vship pship; do cp $OUT/$d/summary.csv $OUT/$d-summary.csv; rm -rf $OUT/$d; done
cat $OUT/md5.txt
