# The kept shadow ground, copied only where needed: a few cases, both renderers (one call).
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
xz -dc .devc/sward-new.xz > /tmp/sn; chmod +x /tmp/sn
B="--warmup 30 --frames 60 --max-seconds 1.5 --width 1920 --height 1080 --quality high"
for r in vulkan wgpu; do
  /tmp/sn bench $B --renderer $r --presets cis565 --counts 2^20 --modes all --out /tmp/c > /dev/null 2>&1; echo "cis565 $r $(tail -1 /tmp/c/summary.csv)" >> $OUT/kept2.txt
  /tmp/sn bench $B --renderer $r --scene meadow --out /tmp/m > /dev/null 2>&1; echo "meadow $r $(tail -1 /tmp/m/summary.csv)" >> $OUT/kept2.txt
  /tmp/sn bench $B --renderer $r --scene trample --out /tmp/t > /dev/null 2>&1; echo "trample $r $(tail -1 /tmp/t/summary.csv)" >> $OUT/kept2.txt
done
cut -d, -f6,20 $OUT/kept2.txt
