# Where the portable renderer's frame goes: both renderers, the shipped meadow and instanced 2^26,
# as they are, without shadows, with strips only, without 64-bit atomics (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; chmod +x /tmp/sn
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/device.txt
B="--warmup 30 --frames 60 --max-seconds 1.5 --width 1920 --height 1080 --quality high"
for r in vulkan wgpu; do
  for v in "as-is:" "no-shadows:--set shading.shadows=false" "strips:--draw-route strips" "no-int64:--without int64-atomics"; do
    name=${v%%:*}; extra=${v#*:}
    /tmp/sn bench $B --renderer $r --scene meadow $extra --out /tmp/m > /dev/null 2>&1
    echo "meadow $r $name $(tail -1 /tmp/m/summary.csv)" >> $OUT/probe.txt
    /tmp/sn bench $B --renderer $r --presets meadow --technique instanced --counts 2^26 --modes all $extra --out /tmp/i > /dev/null 2>&1
    echo "instanced26 $r $name $(tail -1 /tmp/i/summary.csv)" >> $OUT/probe.txt
  done
done
head -1 /tmp/m/summary.csv > $OUT/header.txt
cut -c1-400 $OUT/probe.txt
