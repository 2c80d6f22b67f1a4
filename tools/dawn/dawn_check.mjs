#!/usr/bin/env node
// dawn_check: validate the WGSL of a volfog export folder with Dawn/Tint
// (npm package `webgpu`, i.e. dawn.node), entry point by entry point.
//
// usage: node dawn_check.mjs --manifest DIR/manifest.json
//                            [--backend null|opengl] [--variant NAME]...
//
// For every entry point of the manifest (or of the named variants):
//   1. creates the shader module from its `files.wgsl` and fails on any
//      error of getCompilationInfo() (warnings are printed to stderr);
//   2. builds one GPUBindGroupLayout per group from the manifest's `bindings`
//      (visibility = the stage(s) using them; empty layouts fill gaps) and a
//      GPUPipelineLayout;
//   3. creates the pipeline with create{Compute,Render}PipelineAsync inside
//      validation + internal error scopes.  A fragment entry is paired with
//      the vertex entry named by its `vertex` field; a vertex entry alone gets
//      a vertex-only pipeline with a depth32float attachment.
// Prints one line per entry point, "<variant> <entry> (<stage>): ok" or
// "...: FAIL: <message>", then the summary line {"passed": N, "failed": M}.
// Exit status: 0 all passed, 1 some failed, 2 usage / manifest / device error.
//
// Backends (see README.md):
//   null    Dawn's null backend, core WebGPU feature level: WGSL + pipeline
//           validation only, nothing reaches a driver.  Default.
//   opengl  Dawn's desktop-GL backend on Mesa through EGL surfaceless
//           (EGL_PLATFORM=surfaceless is set here if unset).  Dawn exposes GL
//           only at the "compatibility" feature level, so compat-mode rules
//           apply, and Tint's GLSL output is really compiled by Mesa.

import { readFileSync } from 'node:fs';
import { dirname, resolve } from 'node:path';

const TOOL = 'dawn_check';

function usage() {
  return `usage: node dawn_check.mjs --manifest DIR/manifest.json [--backend null|opengl] [--variant NAME]...`;
}

// Error for bad input (command line, manifest): exit status 2.
class UsageError extends Error {}

function parseArgs(argv) {
  const opts = { manifest: null, backend: 'null', variants: [] };
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i];
    const next = () => {
      if (i + 1 >= argv.length) throw new UsageError(`${arg} needs a value`);
      return argv[++i];
    };
    if (arg === '--manifest') opts.manifest = next();
    else if (arg === '--backend') opts.backend = next();
    else if (arg === '--variant') opts.variants.push(next());
    else if (arg === '-h' || arg === '--help') {
      console.log(usage());
      process.exit(0);
    } else throw new UsageError(`unknown argument '${arg}'`);
  }
  if (!opts.manifest) throw new UsageError('--manifest is required');
  if (!['null', 'opengl'].includes(opts.backend)) {
    throw new UsageError(`unknown backend '${opts.backend}' (null, opengl)`);
  }
  return opts;
}

// ------------------------------------------------------------- device ---

// Returns {gpu, adapter, device} for the requested Dawn backend.  No optional
// features are requested.  Limits: null uses WebGPU's default (guaranteed)
// core limits, so the check is against what every WebGPU device offers;
// opengl requests every limit the adapter supports, because compatibility
// mode's defaults (e.g. maxStorageBuffersInVertexStage = 0) would hide what
// that run is for: Tint's GLSL compiled by the real driver.
async function openDevice(backend) {
  if (backend === 'opengl' && !process.env.EGL_PLATFORM) {
    // Must be set before Dawn initialises EGL: there is no X / Wayland here.
    process.env.EGL_PLATFORM = 'surfaceless';
  }
  const { create, globals } = await import('webgpu');
  Object.assign(globalThis, globals); // GPUShaderStage, GPUBufferUsage, ...
  const gpu = create([`backend=${backend}`]);
  const adapter = await gpu.requestAdapter(
    backend === 'opengl' ? { featureLevel: 'compatibility' } : {},
  );
  if (!adapter) {
    throw new Error(
      `no Dawn adapter for backend=${backend}` +
        (backend === 'opengl' ? ' (needs Mesa EGL with EGL_MESA_platform_surfaceless)' : ''),
    );
  }
  const requiredLimits = {};
  if (backend === 'opengl') {
    for (const name in adapter.limits) requiredLimits[name] = adapter.limits[name];
  }
  const device = await adapter.requestDevice({ requiredLimits });
  device.lost.then((info) => {
    if (info.reason !== 'destroyed') console.error(`${TOOL}: device lost: ${info.message}`);
  });
  return { gpu, adapter, device };
}

// ---------------------------------------------------- manifest → WebGPU ---

const STAGE_BITS = { compute: 0x4, vertex: 0x1, fragment: 0x2 }; // GPUShaderStage

// One manifest `resource` → the resource-type member of a
// GPUBindGroupLayoutEntry.
function layoutResource(binding) {
  const r = binding.resource || {};
  switch (r.kind) {
    case 'buffer':
      return {
        buffer: { type: r.type, hasDynamicOffset: false, minBindingSize: r.size ?? 0 },
      };
    case 'texture':
      return {
        texture: {
          sampleType: r.sample_type,
          viewDimension: r.view_dimension,
          multisampled: !!r.multisampled,
        },
      };
    case 'storage_texture':
      return {
        storageTexture: { access: r.access, format: r.format, viewDimension: r.view_dimension },
      };
    case 'sampler':
      return { sampler: { type: r.type } };
    default:
      throw new Error(`binding '${binding.name}' has unknown resource kind '${r.kind}'`);
  }
}

// Builds the GPUPipelineLayout for a list of [stage, bindings] pairs: the
// bindings of all stages are merged by (group, binding), the visibility being
// the stages that list them; a slot described differently by two stages is
// an error.
function pipelineLayout(device, label, stages) {
  const slots = new Map(); // "group:binding" -> {group, entry, json}
  for (const [stage, bindings] of stages) {
    for (const b of bindings || []) {
      const key = `${b.group}:${b.binding}`;
      const resource = layoutResource(b);
      const json = JSON.stringify(resource);
      const slot = slots.get(key);
      if (!slot) {
        slots.set(key, {
          group: b.group,
          json,
          entry: { binding: b.binding, visibility: STAGE_BITS[stage], ...resource },
        });
      } else if (slot.json !== json) {
        throw new Error(
          `@group(${b.group}) @binding(${b.binding}) ('${b.name}') is described differently ` +
            `by the ${stage} stage: ${json} vs ${slot.json}`,
        );
      } else {
        slot.entry.visibility |= STAGE_BITS[stage];
      }
    }
  }
  const groups = [];
  for (const { group, entry } of slots.values()) {
    while (groups.length <= group) groups.push([]);
    groups[group].push(entry);
  }
  const bindGroupLayouts = groups.map((entries, i) =>
    device.createBindGroupLayout({ label: `${label} group ${i}`, entries }),
  );
  return device.createPipelineLayout({ label, bindGroupLayouts });
}

function blendComponent(c) {
  return { srcFactor: c.src_factor, dstFactor: c.dst_factor, operation: c.operation };
}

// `color_targets` → GPUFragmentState.targets (indexed by location; first
// format of each target; null for unused locations).
function colorTargets(entry) {
  const targets = [];
  for (const t of entry.color_targets || []) {
    while (targets.length <= t.location) targets.push(null);
    targets[t.location] = {
      format: t.formats[0],
      blend: t.blend
        ? { color: blendComponent(t.blend.color), alpha: blendComponent(t.blend.alpha) }
        : undefined,
    };
  }
  return targets;
}

function vertexBuffers(entry) {
  return (entry.vertex_buffers || []).map((vb) => ({
    arrayStride: vb.array_stride,
    stepMode: vb.step_mode || 'vertex',
    attributes: vb.attributes.map((a) => ({
      shaderLocation: a.shader_location,
      format: a.format,
      offset: a.offset,
    })),
  }));
}

function primitiveState(p) {
  if (!p) return undefined;
  return { topology: p.topology, frontFace: p.front_face, cullMode: p.cull_mode };
}

// ---------------------------------------------------------- checking ---

// Shader modules by WGSL path, so a file shared by several entry points is
// compiled (and its warnings printed) once.
class Modules {
  constructor(device, root) {
    this.device = device;
    this.root = root;
    this.cache = new Map();
  }

  // Resolves to the GPUShaderModule of `entry`, or throws with the
  // compilation errors as "FILE:LINE:COL: error: ..." lines.
  get(entry) {
    const rel = entry.files?.wgsl;
    if (!rel) return Promise.reject(new Error(`entry '${entry.name}' has no files.wgsl`));
    if (!this.cache.has(rel)) this.cache.set(rel, this.compile(rel));
    return this.cache.get(rel);
  }

  async compile(rel) {
    const path = resolve(this.root, rel);
    const code = readFileSync(path, 'utf8');
    this.device.pushErrorScope('validation');
    const module = this.device.createShaderModule({ label: rel, code });
    const info = await module.getCompilationInfo();
    const scopeError = await this.device.popErrorScope();
    const errors = [];
    for (const m of info.messages) {
      const text = `${rel}:${m.lineNum}:${m.linePos}: ${m.type}: ${m.message}`;
      if (m.type === 'error') errors.push(text);
      else console.error(text);
    }
    if (errors.length) throw new Error(errors.join('\n'));
    if (scopeError) throw new Error(`${rel}: ${scopeError.message}`);
    return module;
  }
}

// Runs `create` (which creates layouts and a pipeline) inside validation and
// internal error scopes; throws with every error found, root cause first: an
// error captured by a scope (e.g. an invalid bind group layout) comes before
// the rejection of the pipeline creation that it caused.
async function withErrorScopes(device, create) {
  device.pushErrorScope('validation');
  device.pushErrorScope('internal');
  let thrown = null;
  try {
    await create();
  } catch (e) {
    thrown = e;
  }
  const internal = await device.popErrorScope();
  const validation = await device.popErrorScope();
  const errors = [validation, internal, thrown].filter(Boolean);
  if (errors.length) throw new Error(errors.map((e) => e.message || String(e)).join('\n'));
}

// Validates one entry point; throws on failure.
async function checkEntry(device, modules, manifest, variant, entry) {
  const label = `${variant.name}/${entry.name}`;
  if (entry.stage === 'compute') {
    const module = await modules.get(entry);
    await withErrorScopes(device, () =>
      device.createComputePipelineAsync({
        label,
        layout: pipelineLayout(device, label, [['compute', entry.bindings]]),
        compute: { module, entryPoint: entry.name },
      }),
    );
  } else if (entry.stage === 'vertex') {
    // No fragment stage: a render pipeline needs an attachment, so give it
    // a depth buffer it never writes.
    const module = await modules.get(entry);
    await withErrorScopes(device, () =>
      device.createRenderPipelineAsync({
        label,
        layout: pipelineLayout(device, label, [['vertex', entry.bindings]]),
        vertex: { module, entryPoint: entry.name, buffers: vertexBuffers(entry) },
        primitive: primitiveState(entry.primitive),
        depthStencil: { format: 'depth32float', depthWriteEnabled: false, depthCompare: 'always' },
      }),
    );
  } else if (entry.stage === 'fragment') {
    const vs = findVertex(manifest, entry);
    const [vsModule, fsModule] = await Promise.all([modules.get(vs), modules.get(entry)]);
    await withErrorScopes(device, () =>
      device.createRenderPipelineAsync({
        label,
        layout: pipelineLayout(device, label, [
          ['vertex', vs.bindings],
          ['fragment', entry.bindings],
        ]),
        vertex: { module: vsModule, entryPoint: vs.name, buffers: vertexBuffers(vs) },
        primitive: primitiveState(entry.primitive || vs.primitive),
        fragment: { module: fsModule, entryPoint: entry.name, targets: colorTargets(entry) },
      }),
    );
  } else {
    throw new Error(`unknown stage '${entry.stage}'`);
  }
}

// The vertex entry a fragment entry is paired with (its `vertex` field).
function findVertex(manifest, entry) {
  const ref = entry.vertex;
  if (!ref) throw new Error('fragment entry names no vertex shader ("vertex" field)');
  const variant = manifest.variants.find((v) => v.name === ref.variant);
  const vs = variant?.entry_points.find((e) => e.name === ref.entry && e.stage === 'vertex');
  if (!vs) throw new Error(`vertex shader ${ref.variant}/${ref.entry} is not in the manifest`);
  return vs;
}

// Dawn messages span several lines ("...\n - While ..."): keep them on one.
function oneLine(message) {
  return message
    .split('\n')
    .map((l) => l.trim())
    .filter(Boolean)
    .join(' | ');
}

async function main() {
  let opts, manifest;
  try {
    opts = parseArgs(process.argv.slice(2));
    try {
      manifest = JSON.parse(readFileSync(opts.manifest, 'utf8'));
    } catch (e) {
      throw new UsageError(`${opts.manifest}: cannot read manifest: ${e.message}`);
    }
    if (!Array.isArray(manifest.variants)) {
      throw new UsageError(`${opts.manifest}: no "variants" array`);
    }
    for (const name of opts.variants) {
      if (!manifest.variants.some((v) => v.name === name)) {
        throw new UsageError(`${opts.manifest}: no variant '${name}'`);
      }
    }
  } catch (e) {
    if (!(e instanceof UsageError)) throw e;
    console.error(`${TOOL}: ${e.message}\n${usage()}`);
    return 2;
  }

  // Keep the whole {gpu, adapter, device} alive until the end: if the object
  // returned by create() is garbage-collected, dawn.node tears the instance
  // down under the device and the process aborts.
  let dawn;
  try {
    dawn = await openDevice(opts.backend);
  } catch (e) {
    const hint = e.code === 'ERR_MODULE_NOT_FOUND' ? ' (run tools/dawn/install.sh)' : '';
    console.error(`${TOOL}: ${e.message}${hint}`);
    return 2;
  }

  const { device } = dawn;
  const modules = new Modules(device, dirname(resolve(opts.manifest)));
  const selected = manifest.variants.filter(
    (v) => opts.variants.length === 0 || opts.variants.includes(v.name),
  );
  let passed = 0;
  let failed = 0;
  for (const variant of selected) {
    for (const entry of variant.entry_points || []) {
      const what = `${variant.name} ${entry.name} (${entry.stage})`;
      try {
        await checkEntry(device, modules, manifest, variant, entry);
        console.log(`${what}: ok`);
        passed++;
      } catch (e) {
        console.log(`${what}: FAIL: ${oneLine(e.message)}`);
        failed++;
      }
    }
  }
  console.log(JSON.stringify({ passed, failed }));
  device.destroy();
  dawn = null;
  return failed ? 1 : 0;
}

// dawn.node keeps the process alive while its instance exists: exit
// explicitly once done.
main().then(
  (code) => process.exit(code),
  (e) => {
    console.error(`${TOOL}: ${e.stack || e}`);
    process.exit(2);
  },
);
