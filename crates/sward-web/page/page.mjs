// sward's portable renderer in the browser (sward-web, built by wasm-bindgen into sward_web.js):
// reads plan.json, times each case with each far-field route (alternating their order from one
// repeat to the next, so a drifting machine favours neither), renders the shots asked for (each
// read back as RGBA, row by row from the top), and
// posts the results back to the runner (crates/sward-wgpu/tests/browser/run.mjs).
import init, { describe, bench, render, render_toml } from './sward_web.js';

const post = (name, body) => fetch(`/out/${name}`, { method: 'POST', body });
const said = [];

async function main() {
  await init();
  const plan = await (await fetch('plan.json')).json();
  said.push(`adapter: ${await describe()}`);
  const results = [];
  for (let repeat = 0; repeat < plan.repeats; repeat++) {
    for (const name of plan.cases) {
      const routes = repeat % 2 ? [...plan.routes].reverse() : plan.routes;
      for (const route of routes) {
        const times = await bench(name, route, plan.width, plan.height, plan.warmup, plan.frames);
        results.push({ case: name, route, repeat, times: Array.from(times) });
        await post('results.json', JSON.stringify(results));
      }
    }
  }
  // A shot is a case by name, or a scene file the runner hands over (a test's own scene).
  for (const [k, shot] of (plan.shots ?? []).entries()) {
    const size = [plan.width, plan.height, plan.shot_steps];
    const rgba = shot.toml
      ? await render_toml(shot.toml, shot.route, ...size)
      : await render(shot.name, shot.route, ...size);
    await post(`shot-${k}.rgba`, rgba);
    said.push(`shot ${k}: ${shot.name ?? 'scene file'} ${shot.route}`);
  }
}

main()
  .catch((e) => said.push(`error: ${e?.message ?? e}`))
  .finally(() => post('done', said.join('\n')));
