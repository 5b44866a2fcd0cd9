// The page run.mjs opens: every portable pipeline's WGSL compiled by the browser's WebGPU (each
// compilation message kept), every pipeline made, then the fixture's field simulated frame by
// frame and another culled into distance buckets; the buffers posted back for the Rust test to
// compare with sward-core's CPU reference.
const messages = [];
const post = (name, body) => fetch(`/out/${name}`, { method: 'POST', body });
const bytes = async (name) => new Uint8Array(await (await fetch(name)).arrayBuffer());
const WORKGROUP = 64;
// The binding numbers sward-core declares (bindings.json: BINDING_NAME → number), by NAME.
let B = {};
// The frame's uniform blocks (frame-blocks.json: binding, offset, size each), and the blocks
// each pipeline reads (pipelines.json's `reads`): where a pass binds the frame's buffer
// (`FRAME`), its pipeline's group holds those blocks, each a range of the buffer.
const FRAME = 'frame';
let BLOCKS = [];
const reads = new Map();
// The numbers sward-core declares for the shaders' commands and counters (numbers.json: NAME →
// number): the distance buckets, and where the cull's counters hold what.
let N = {};

async function main() {
  if (!navigator.gpu) throw new Error('this browser has no WebGPU (navigator.gpu is missing)');
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) throw new Error('WebGPU gives no adapter');
  const info = adapter.info ?? {};
  // WebGPU's default limits: what every browser offers; and subgroups where the adapter has
  // them, as the portable renderer asks for them.
  const subgroups = adapter.features.has('subgroups');
  const named = `${info.vendor ?? ''} ${info.architecture ?? ''} ${info.description ?? ''}`.trim();
  messages.push(`adapter: ${named}${subgroups ? ', with subgroups' : ''}`);
  const device = await adapter.requestDevice({ requiredFeatures: subgroups ? ['subgroups'] : [] });
  device.onuncapturederror = (e) => messages.push(`error: ${e.error.message}`);
  const pipelines = await (await fetch('pipelines.json')).json();
  const declared = await (await fetch('bindings.json')).json();
  B = Object.fromEntries(Object.entries(declared).map(([name, n]) => [name.replace(/^BINDING_/, ''), n]));
  BLOCKS = await (await fetch('frame-blocks.json')).json();
  N = await (await fetch('numbers.json')).json();
  const made = {};
  for (const p of pipelines.filter((p) => !p.narrow)) {
    // A pipeline that uses subgroups begins with WGSL's enable directive, as sward writes it
    // for a browser (PipelineSource::browser_text; wgpu's naga refuses it). Without the
    // feature, it is not made.
    const usesSubgroups = p.code.startsWith('enable subgroups;');
    if (usesSubgroups && !subgroups) continue;
    const code = p.code;
    device.pushErrorScope('validation');
    const module = device.createShaderModule({ label: p.name, code });
    const compiled = await module.getCompilationInfo();
    for (const m of compiled.messages) {
      messages.push(`${m.type}: ${p.name} line ${m.lineNum}: ${m.message}`);
    }
    made[p.name] = await makePipeline(device, module, p);
    reads.set(made[p.name], p.reads);
    const error = await device.popErrorScope();
    if (error) messages.push(`error: ${p.name}: ${error.message}`);
  }
  await makeNarrowSplatting(pipelines.filter((p) => p.narrow));
  await simulate(device, made.simulate);
  // The cull the portable renderer runs here: with subgroups where the device has them.
  const passes = ['count_buckets', 'scan_buckets', 'place_blades']
    .map((name) => subgroups ? `${name}_subgroups` : name);
  // The lay-out that sizes the sort's runs, and the strips' blades sorted by exact distance,
  // within WebGPU's default limits.
  const [count, scan, place] = passes;
  const cullPasses = [count, 'lay_out_buckets_narrow', scan, place, 'sort_drawn_narrow'];
  await cull(device, cullPasses.map((name) => made[name]));
}

// The splatting passes in 32-bit cells (the far field of a device without 64-bit atomics), made
// as the portable renderer makes them in a browser: within WebGPU's default limits (8 storage
// buffers a stage, workgroups of 256 at most), on a device without subgroups.
async function makeNarrowSplatting(narrow) {
  // An adapter of its own: one makes one device.
  const adapter = await navigator.gpu.requestAdapter();
  const device = await adapter.requestDevice();
  const binds = device.limits.maxStorageBuffersPerShaderStage;
  device.onuncapturederror = (e) => messages.push(`error: narrow splatting: ${e.error.message}`);
  let made = 0;
  for (const p of narrow) {
    device.pushErrorScope('validation');
    const module = device.createShaderModule({ label: p.name, code: p.code });
    const compiled = await module.getCompilationInfo();
    for (const m of compiled.messages) {
      messages.push(`${m.type}: ${p.name} line ${m.lineNum}: ${m.message}`);
    }
    const constants = {};
    for (const [, id, name] of p.code.matchAll(/@id\((\d+)\)\s*override\s+(\w+)/g)) {
      if (name.endsWith('WORKGROUP')) constants[id] = 256;
    }
    try {
      await makeNarrow(device, module, p, constants);
    } catch (e) {
      messages.push(`error: ${p.name}: ${e.message ?? e}`);
    }
    const error = await device.popErrorScope();
    if (error) messages.push(`error: ${p.name}: ${error.message}`);
    else made += 1;
  }
  messages.push(`narrow: ${made} of ${narrow.length} splatting pipelines made, ${binds} storage buffers a stage`);
}

function makeNarrow(device, module, p, constants) {
    if (p.fragment) {
      return device.createRenderPipelineAsync({
        layout: 'auto',
        vertex: { module, entryPoint: p.entry },
        fragment: { module, entryPoint: p.fragment, targets: [{ format: 'rgba8unorm-srgb' }] },
        depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'always' },
        multisample: { count: 4 },
      });
    }
    return device.createComputePipelineAsync({ layout: 'auto', compute: { module, entryPoint: p.entry, constants } });
}

function makePipeline(device, module, p) {
  if (p.vertex_only) {
    // The sun's shadow map's casters: a vertex stage alone, depth only.
    const strips = p.name === 'shadow_blades' || p.name === 'shadow_generated';
    return device.createRenderPipelineAsync({
      layout: 'auto',
      vertex: { module, entryPoint: p.entry },
      primitive: { topology: strips ? 'triangle-strip' : 'triangle-list' },
      depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
    });
  }
  if (!p.fragment) {
    return device.createComputePipelineAsync({ layout: 'auto', compute: { module, entryPoint: p.entry } });
  }
  if (p.name.startsWith('occluder_')) {
    // The depth pyramid's occluders: the bits of their depth, one sample.
    return device.createRenderPipelineAsync({
      layout: 'auto',
      vertex: { module, entryPoint: p.entry },
      fragment: { module, entryPoint: p.fragment, targets: [{ format: 'r32uint' }] },
      primitive: { topology: p.name === 'occluder_blades' ? 'triangle-strip' : 'triangle-list' },
      depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
    });
  }
  return device.createRenderPipelineAsync({
    layout: 'auto',
    vertex: { module, entryPoint: p.entry },
    fragment: { module, entryPoint: p.fragment, targets: [{ format: 'rgba8unorm-srgb' }] },
    primitive: { topology: p.name === 'strips' ? 'triangle-strip' : 'triangle-list' },
    depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
    multisample: { count: 4 },
  });
}

const STORAGE = GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC | GPUBufferUsage.COPY_DST;

function buffer(device, size, usage, data) {
  const b = device.createBuffer({ size: Math.max(size, 16), usage, mappedAtCreation: !!data });
  if (data) {
    new Uint8Array(b.getMappedRange()).set(data);
    b.unmap();
  }
  return b;
}

function dispatch(device, encoder, pipeline, entries, x) {
  const bound = entries.flatMap(([binding, b]) => binding !== FRAME ? [{ binding, resource: { buffer: b } }]
    : BLOCKS.filter(([block]) => reads.get(pipeline).includes(block))
      .map(([block, offset, size]) => ({ binding: block, resource: { buffer: b, offset, size } })));
  const bind = device.createBindGroup({ layout: pipeline.getBindGroupLayout(0), entries: bound });
  const pass = encoder.beginComputePass();
  pass.setPipeline(pipeline);
  pass.setBindGroup(0, bind);
  // A count of workgroups, or [buffer, offset] of the dispatch's size.
  if (Array.isArray(x)) pass.dispatchWorkgroupsIndirect(x[0], x[1]);
  else pass.dispatchWorkgroups(x, 1, 1);
  pass.end();
}

async function readBack(device, source) {
  const staging = device.createBuffer({ size: source.size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
  const encoder = device.createCommandEncoder();
  encoder.copyBufferToBuffer(source, 0, staging, 0, source.size);
  device.queue.submit([encoder.finish()]);
  await staging.mapAsync(GPUMapMode.READ);
  const copy = new Uint8Array(staging.getMappedRange()).slice();
  staging.unmap();
  return copy;
}

// The fixture's frames (each the frame's uniforms, one after another) over its blades.
async function simulate(device, pipeline) {
  const blades = await bytes('simulate-blades.bin');
  const frames = await bytes('simulate-frames.bin');
  const frameSize = Number(await (await fetch('frame-size.txt')).text());
  const count = blades.length / 64;
  const bladeBuffer = buffer(device, blades.length, STORAGE, blades);
  const etas = buffer(device, count * 4, STORAGE, new Uint8Array(count * 4));
  const frame = buffer(device, frameSize, GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST);
  // The trample map's texels, the tiles run, the ground's height grid and the paint (unread: the
  // fixture's frames have the map off, the field no tiles and no streamed twins to ease into).
  const trample = buffer(device, 16, STORAGE);
  const tiles = buffer(device, 16, STORAGE);
  const ground = buffer(device, 32, STORAGE);
  const paint = buffer(device, 16, STORAGE);
  for (let at = 0; at < frames.length; at += frameSize) {
    device.queue.writeBuffer(frame, 0, frames, at, frameSize);
    const encoder = device.createCommandEncoder();
    const bound = [[FRAME, frame], [B.BLADES, bladeBuffer], [B.ETAS, etas], [B.GROUND, ground],
      [B.TRAMPLE, trample], [B.ACTIVE_TILES, tiles], [B.PAINT, paint]];
    dispatch(device, encoder, pipeline, bound, Math.ceil(count / WORKGROUP));
    device.queue.submit([encoder.finish()]);
  }
  await post('simulated-blades', await readBack(device, bladeBuffer));
  await post('simulated-etas', await readBack(device, etas));
}

// The fixture's cull frame over its blades: count, lay out, scan, place.
async function cull(device, [count, layOut, scan, place, sort]) {
  const blades = await bytes('cull-blades.bin');
  const frameBytes = await bytes('cull-frame.bin');
  const n = blades.length / 64;
  const frame = buffer(device, frameBytes.length, GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST, frameBytes);
  const bladeBuffer = buffer(device, blades.length, STORAGE, blades);
  const visible = buffer(device, n * 4, STORAGE);
  const bucketOf = buffer(device, n * 4, STORAGE);
  // A command per bucket, the blade occluders', the far buckets' splat dispatch and the sort's.
  const draws = buffer(device, (N.DISTANCE_BUCKETS + 3) * 16, STORAGE | GPUBufferUsage.INDIRECT);
  // Per bucket its count and start, then the buckets drawn, the workgroups counted and the
  // bucket the occluders' budget cuts (its start and its blades).
  const counters = buffer(device, (N.OCCLUDER_CUT + 2) * 4, STORAGE);
  const encoder = device.createCommandEncoder();
  encoder.clearBuffer(counters);
  const groups = Math.ceil(n / WORKGROUP);
  // Each workgroup's blades per bucket, then where its run of each bucket starts.
  const runs = buffer(device, N.DISTANCE_BUCKETS * groups * 4, STORAGE);
  // The depth pyramid's levels (unread: the fixture's cull has no occlusion test).
  const hiz = buffer(device, 4 * 349525, STORAGE);
  // The tiles run (unread: the fixture's field has none).
  const tiles = buffer(device, 16, STORAGE);
  dispatch(device, encoder, count, [[FRAME, frame], [B.BLADES, bladeBuffer], [B.BUCKET_OF, bucketOf],
    [B.CULL_COUNTERS, counters], [B.CULLED, runs], [B.DEPTH_PYRAMID, hiz], [B.ACTIVE_TILES, tiles]], groups);
  dispatch(device, encoder, layOut, [[FRAME, frame], [B.DRAWS, draws], [B.CULL_COUNTERS, counters]], 1);
  dispatch(device, encoder, scan, [[B.CULL_COUNTERS, counters], [B.CULLED, runs]], N.DISTANCE_BUCKETS);
  dispatch(device, encoder, place, [[FRAME, frame], [B.VISIBLE, visible], [B.BUCKET_OF, bucketOf],
    [B.CULL_COUNTERS, counters], [B.CULLED, runs], [B.ACTIVE_TILES, tiles]], groups);
  // Its workgroups as the lay-out wrote them (buckets.wesl SORT_DRAWN_COMMAND).
  dispatch(device, encoder, sort, [[FRAME, frame], [B.BLADES, bladeBuffer], [B.VISIBLE, visible],
    [B.BUCKET_OF, bucketOf], [B.CULL_COUNTERS, counters]], [draws, (N.DISTANCE_BUCKETS + 2) * 16]);
  device.queue.submit([encoder.finish()]);
  await post('visible', await readBack(device, visible));
  await post('draws', await readBack(device, draws));
  await post('counters', await readBack(device, counters));
}

main()
  .catch((e) => messages.push(`error: ${e.message ?? e}`))
  .finally(() => post('done', messages.join('\n')));
