# One device call: the gallery and assets examples' pictures at 1920x1080 on Bevy's own device, three
# presets from their own cameras at 1920x1080 on the Vulkan renderer, and the regression set before
# (the shaders of 560ee5a through --shaders) and after the flowering heads' width and shape.
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
mkdir -p /tmp/libs /tmp/use; for f in .devg/*.deb; do dpkg -x $f /tmp/libs; done
for l in libwayland-client.so.0 libudev.so.1 libffi.so.8; do
  ldconfig -p | grep -q "^\s*$l " || { find /tmp/libs -name "$l*" -exec cp -a {} /tmp/use/ \; ; echo "carried $l" >> $OUT/log.txt; }
done
[ -e /usr/share/vulkan/icd.d/nvidia_icd.json ] || [ -e /etc/vulkan/icd.d/nvidia_icd.json ] || export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
for b in sward gallery assets paint; do xz -dc .devg/$b.xz > /tmp/$b && chmod +x /tmp/$b; done
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader >> $OUT/log.txt
t0=$(date +%s)
step() { echo "$1 $(( $(date +%s) - t0 )) s rc=$2" >> $OUT/log.txt; }
for e in gallery paint; do LD_LIBRARY_PATH=/tmp/use timeout 100 /tmp/$e --shot $OUT/bevy-$e.png --frames 300 > /tmp/$e.txt 2>&1; step $e $?; grep -v "VALIDATION\|objects:" /tmp/$e.txt | tail -3 >> $OUT/log.txt; done
BEVY_ASSET_ROOT=$PWD/crates/sward-bevy LD_LIBRARY_PATH=/tmp/use timeout 100 /tmp/assets --shot $OUT/bevy-assets.png --frames 300 > /tmp/assets.txt 2>&1; step assets $?
grep -v "VALIDATION\|objects:" /tmp/assets.txt | tail -4 >> $OUT/log.txt
for p in wildflower-meadow pampas reed-marsh; do
  timeout 60 /tmp/sward render --scene crates/sward-bevy/src/presets/$p.grass.toml --width 1920 --height 1080 --out $OUT/$p.png > /tmp/$p.txt 2>&1; step $p $?
done
B="--regression-set --warmup 40 --frames 100 --max-seconds 2 --quality high"
timeout 150 /tmp/sward bench $B --shaders .devg/old-shaders --out /tmp/before > /tmp/before.txt 2>&1; step before $?
timeout 150 /tmp/sward bench $B --out /tmp/after > /tmp/after.txt 2>&1; step after $?
/tmp/sward bench --compare /tmp/before /tmp/after > $OUT/compare.txt 2>&1; step compare $?
# The wildflower meadow, flowers and all, at 1920x1080: old shaders against new.
W="--scene crates/sward-bevy/src/presets/wildflower-meadow.grass.toml --width 1920 --height 1080 --warmup 60 --frames 200 --max-seconds 3"
timeout 60 /tmp/sward bench $W --shaders .devg/old-shaders --out /tmp/wf-before > /tmp/wfb.txt 2>&1; step wf-before $?
timeout 60 /tmp/sward bench $W --out /tmp/wf-after > /tmp/wfa.txt 2>&1; step wf-after $?
/tmp/sward bench --compare /tmp/wf-before /tmp/wf-after > $OUT/compare-wf.txt 2>&1; step compare-wf $?
if [ $(( $(date +%s) - t0 )) -lt 380 ]; then
  timeout 120 /tmp/sward bench $B --out /tmp/after2 > /tmp/after2.txt 2>&1; step after2 $?
  timeout 120 /tmp/sward bench $B --shaders .devg/old-shaders --out /tmp/before2 > /tmp/before2.txt 2>&1; step before2 $?
  /tmp/sward bench --compare /tmp/before2 /tmp/after2 > $OUT/compare2.txt 2>&1; step compare2 $?
fi
tar -C /tmp -cJf $OUT/runs.tar.xz before after before2 after2 wf-before wf-after before.txt after.txt wfb.txt wfa.txt 2>/dev/null
cat $OUT/compare.txt $OUT/compare2.txt $OUT/compare-wf.txt 2>/dev/null | head -80
cat $OUT/log.txt
