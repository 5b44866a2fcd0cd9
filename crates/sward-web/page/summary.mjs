// The browser bench's results (out-results.json, posted by page.mjs) as a table and a CSV: each
// case's median and p99 frame by far-field route, the lesser median of the repeats (a repeat
// that ran while the machine was busy says nothing of the route), and splatted / drawn.
//
//   node summary.mjs OUT_DIR
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

const out = process.argv[2];
const said = readFileSync(join(out, 'out-done'), 'utf8');
const problems = said.split('\n').filter((l) => l.startsWith('error:'));
if (problems.length) {
  console.error(`the page failed: ${problems.join(' | ')}`);
  process.exit(1);
}
const results = JSON.parse(readFileSync(join(out, 'out-results.json'), 'utf8'));
const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};
const best = new Map();
for (const r of results) {
  const key = `${r.case}\t${r.route}`;
  const row = { median: quantile(r.times, 0.5), p99: quantile(r.times, 0.99), frames: r.times.length };
  if (!best.has(key) || row.median < best.get(key).median) best.set(key, row);
}
const cases = [...new Set(results.map((r) => r.case))];
const adapter = said.split('\n').find((l) => l.startsWith('adapter:')) ?? 'adapter: unknown';
const csv = ['case,route,frames,median_ms,p99_ms'];
console.log(`${adapter}\n\n| case | drawn ms (p99) | splatted ms (p99) | splatted / drawn |\n|---|---|---|---|`);
for (const c of cases) {
  const [drawn, splatted] = ['drawn', 'splatted'].map((route) => best.get(`${c}\t${route}`));
  for (const [route, r] of [['drawn', drawn], ['splatted', splatted]]) {
    if (r) csv.push(`"${c}",${route},${r.frames},${r.median.toFixed(2)},${r.p99.toFixed(2)}`);
  }
  if (!drawn || !splatted) continue;
  const ms = (r) => `${r.median.toFixed(1)} (${r.p99.toFixed(1)})`;
  console.log(`| ${c} | ${ms(drawn)} | ${ms(splatted)} | ${(splatted.median / drawn.median).toFixed(2)}× |`);
}
writeFileSync(join(out, 'summary.csv'), `${csv.join('\n')}\n`);
