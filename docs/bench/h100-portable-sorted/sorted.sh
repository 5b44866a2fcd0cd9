# The portable renderer with its strips sorted and its passes as SPIR-V: both renderers' regression sets and
# shipped tables, the Vulkan renderer's regression set against the binary before the sort moved (alternated),
# md5 twice for both renderers (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; xz -dc .devc/sward-old.xz > /tmp/so; chmod +x /tmp/sn /tmp/so
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/log.txt
t0=$(date +%s)
step() { echo "$1 $(( $(date +%s) - t0 )) s" >> $OUT/log.txt; }
V="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
S="--shipped --warmup 40 --frames 100 --max-seconds 2"
mkdir -p /tmp/s
for run in "sn:vnew:$V" "sn:pnew:$V --renderer wgpu" "sn:vship:$S" "sn:pship:$S --renderer wgpu" "so:vold:$V" "sn:vnew2:$V" "so:vold2:$V"; do
  bin=${run%%:*}; rest=${run#*:}; name=${rest%%:*}; args=${rest#*:}
  /tmp/$bin bench $args --out /tmp/$name > /tmp/s/$name.log 2>&1
  cp /tmp/$name/summary.csv /tmp/s/$name-summary.csv; step $name
  tar -C /tmp/s -cf $OUT/summaries.tar .
done
for s in trample trail landscape prairie; do for r in wgpu vulkan; do for i in 1 2; do
  timeout 60 /tmp/sn render --scene $s --renderer $r --width 1920 --height 1080 --steps 60 --out /tmp/$s-$r-$i.png > /dev/null 2>/tmp/s/$s-$r-$i.err
  echo "$s $r $i $(md5sum < /tmp/$s-$r-$i.png | cut -c1-12)" >> $OUT/log.txt
done; done; done
step md5
tar -C /tmp/s -cf $OUT/summaries.tar .
cat $OUT/log.txt
