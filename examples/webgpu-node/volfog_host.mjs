// A WebGPU host for volfog's exported WGSL that reads everything it needs from
// manifest.json: bind group layouts (buffer types and minimum sizes, texture sample
// types and view dimensions, storage texture formats, sampler types), the vertex shader
// a fragment shader is drawn with, colour target formats and blend state, workgroup
// sizes, and the byte layout of every uniform and storage struct (member offsets and
// types), so uniform values given by member name become the bytes the shaders read.
//
// Nothing here is specific to Dawn or Node except `openDevice`; in a browser, pass
// `navigator.gpu`'s device to the same functions.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';

// ------------------------------------------------------------------ device ---

/// A Dawn device from the npm package `webgpu`. `backend` is 'opengl' (runs on Mesa
/// through EGL without a display, in WebGPU compatibility mode) or anything Dawn's
/// `backend=` option takes. Keep the returned `gpu` alive while the device is used.
export async function openDevice(backend = 'opengl') {
  if (backend === 'opengl' && !process.env.EGL_PLATFORM) {
    process.env.EGL_PLATFORM = 'surfaceless';
  }
  const { create, globals } = await import('webgpu');
  Object.assign(globalThis, globals);
  const gpu = create([`backend=${backend}`]);
  const adapter = await gpu.requestAdapter(
    backend === 'opengl' ? { featureLevel: 'compatibility' } : {},
  );
  if (!adapter) throw new Error(`no WebGPU adapter for backend=${backend}`);
  // Compatibility mode's default limits are tiny; ask for what the adapter has.
  const requiredLimits = {};
  for (const name in adapter.limits) requiredLimits[name] = adapter.limits[name];
  const device = await adapter.requestDevice({ requiredLimits });
  device.addEventListener('uncapturederror', (e) => {
    throw new Error(`WebGPU error: ${e.error.message}`);
  });
  return { gpu, adapter, device };
}

// ---------------------------------------------------------------- manifest ---

/// An export folder written by `volfog export --target wgsl` (or `--target all`).
export class VolfogExport {
  constructor(dir) {
    this.dir = dir;
    this.manifest = JSON.parse(readFileSync(join(dir, 'manifest.json'), 'utf8'));
  }

  /// The manifest entry of `variant` (e.g. "scan@default") named `entry`.
  entry(variant, entry) {
    const v = this.manifest.variants.find((x) => x.name === variant);
    if (!v) throw new Error(`variant ${variant} is not in the export`);
    const e = v.entry_points.find((x) => x.name === entry);
    if (!e) throw new Error(`${variant} has no entry point ${entry}`);
    return e;
  }

  /// The WGSL source of an entry point.
  wgsl(entry) {
    if (!entry.files.wgsl) throw new Error(`${entry.name} was not exported as WGSL`);
    return readFileSync(join(this.dir, entry.files.wgsl), 'utf8');
  }
}

// ----------------------------------------------------------- struct layout ---

function parseType(ty) {
  let m;
  if ((m = /^array<(.+), (\d+)>$/.exec(ty))) return { kind: 'array', element: m[1], count: +m[2] };
  if ((m = /^array<(.+)>$/.exec(ty))) return { kind: 'runtime-array', element: m[1] };
  if ((m = /^mat(\d)x(\d)<f32>$/.exec(ty))) return { kind: 'matrix', columns: +m[1], rows: +m[2] };
  if ((m = /^vec(\d)<(f32|u32|i32)>$/.exec(ty))) return { kind: 'vector', n: +m[1], scalar: m[2] };
  if (['f32', 'u32', 'i32'].includes(ty)) return { kind: 'vector', n: 1, scalar: ty };
  return { kind: 'struct', name: ty };
}

function writeScalar(view, offset, scalar, value, what) {
  if (typeof value !== 'number' || !Number.isFinite(value)) {
    throw new Error(`${what}: expected a finite number, got ${JSON.stringify(value)}`);
  }
  if (scalar === 'f32') view.setFloat32(offset, value, true);
  else if (scalar === 'u32') view.setUint32(offset, value, true);
  else view.setInt32(offset, value, true);
}

function numbers(value, count, what) {
  const list = count === 1 && typeof value === 'number' ? [value] : value;
  if (!Array.isArray(list) || list.length !== count) {
    throw new Error(`${what}: expected ${count} numbers, got ${JSON.stringify(value)}`);
  }
  return list;
}

// Writes `value` of WGSL type `ty` at `offset`; `size` is the member's size in the
// manifest (it gives the stride of fixed-size arrays).
function writeValue(view, structs, ty, offset, size, value, what) {
  const t = parseType(ty);
  switch (t.kind) {
    case 'vector':
      numbers(value, t.n, what).forEach((v, i) =>
        writeScalar(view, offset + 4 * i, t.scalar, v, `${what}[${i}]`),
      );
      return;
    case 'matrix': {
      // Column-major, as glam and WGSL hold matrices; vec3 columns are 16 bytes apart.
      const stride = t.rows === 2 ? 8 : 16;
      const list = numbers(value, t.columns * t.rows, what);
      for (let c = 0; c < t.columns; c++) {
        for (let r = 0; r < t.rows; r++) {
          writeScalar(view, offset + c * stride + 4 * r, 'f32', list[c * t.rows + r], `${what}[${c}][${r}]`);
        }
      }
      return;
    }
    case 'array': {
      if (!Array.isArray(value) || value.length !== t.count) {
        throw new Error(`${what}: expected ${t.count} elements`);
      }
      const stride = size / t.count;
      value.forEach((v, i) =>
        writeValue(view, structs, t.element, offset + i * stride, stride, v, `${what}[${i}]`),
      );
      return;
    }
    case 'struct':
      writeStruct(view, structs, t.name, offset, value, what);
      return;
    default:
      throw new Error(`${what}: ${ty} cannot be a member`);
  }
}

function writeStruct(view, structs, name, offset, value, what) {
  const s = structs.find((x) => x.name === name);
  if (!s) throw new Error(`${what}: struct ${name} is not described by the manifest`);
  if (value === null || typeof value !== 'object') throw new Error(`${what}: expected an object`);
  for (const m of s.members) {
    if (!(m.name in value)) throw new Error(`${what}.${m.name}: missing`);
    writeValue(view, structs, m.ty, offset + m.offset, m.size, value[m.name], `${what}.${m.name}`);
  }
}

/// The bytes of a buffer binding (`binding.resource.kind === 'buffer'`) holding
/// `value`: an object with the struct's member names for a struct, an array of such
/// objects for a runtime-sized array (at least one element is written).
export function bufferBytes(entry, binding, value) {
  const r = binding.resource;
  const t = parseType(r.struct);
  let bytes;
  if (t.kind === 'runtime-array') {
    if (!Array.isArray(value)) throw new Error(`${binding.name}: expected an array`);
    bytes = new ArrayBuffer(Math.max(1, value.length) * r.stride);
    const view = new DataView(bytes);
    value.forEach((v, i) =>
      writeValue(view, entry.structs, t.element, i * r.stride, r.stride, v, `${binding.name}[${i}]`),
    );
  } else {
    bytes = new ArrayBuffer(r.size);
    writeValue(new DataView(bytes), entry.structs, r.struct, 0, r.size, value, binding.name);
  }
  return new Uint8Array(bytes);
}

// ---------------------------------------------------------------- layouts ---

const STAGE = { compute: 0x4, vertex: 0x1, fragment: 0x2 }; // GPUShaderStage bits

function layoutEntry(binding, visibility) {
  const r = binding.resource;
  const entry = { binding: binding.binding, visibility };
  switch (r.kind) {
    case 'buffer':
      entry.buffer = { type: r.type, minBindingSize: r.size };
      break;
    case 'texture':
      entry.texture = {
        sampleType: r.sample_type,
        viewDimension: r.view_dimension,
        multisampled: r.multisampled,
      };
      break;
    case 'storage_texture':
      entry.storageTexture = { access: r.access, format: r.format, viewDimension: r.view_dimension };
      break;
    case 'sampler':
      entry.sampler = { type: r.type };
      break;
    default:
      throw new Error(`${binding.name}: unknown resource kind ${r.kind}`);
  }
  return entry;
}

/// Bind group layouts for the bindings of one or more entry points (a vertex and a
/// fragment shader share a pipeline layout): `[{ group, entries, bindings }]`.
function groupLayouts(device, label, entries) {
  const groups = [];
  for (const e of entries) {
    for (const b of e.bindings) {
      groups[b.group] ??= new Map();
      const slot = groups[b.group].get(b.binding);
      if (slot) slot.entry.visibility |= STAGE[e.stage];
      else groups[b.group].set(b.binding, { binding: b, entry: layoutEntry(b, STAGE[e.stage]) });
    }
  }
  return Array.from(groups, (slots, group) => {
    const list = slots ? [...slots.values()] : [];
    return {
      group,
      bindings: list.map((s) => s.binding),
      layout: device.createBindGroupLayout({
        label: `${label} group ${group}`,
        entries: list.map((s) => s.entry),
      }),
    };
  });
}

// ----------------------------------------------------------------- passes ---

/// One exported pass ready to run: its pipeline and bind group layouts.
export class Pass {
  /// A compute pass: `entry` of `variant`.
  static compute(device, exp, variant, entry) {
    const e = exp.entry(variant, entry);
    const groups = groupLayouts(device, variant, [e]);
    const pipeline = device.createComputePipeline({
      label: variant,
      layout: device.createPipelineLayout({ bindGroupLayouts: groups.map((g) => g.layout) }),
      compute: { module: device.createShaderModule({ label: variant, code: exp.wgsl(e) }), entryPoint: entry },
    });
    return new Pass(variant, e, groups, pipeline);
  }

  /// A render pass: fragment `entry` of `variant`, drawn with the vertex shader the
  /// manifest names, onto a colour target of `format` (one the manifest lists).
  static render(device, exp, variant, entry, format) {
    const fs = exp.entry(variant, entry);
    const vs = exp.entry(fs.vertex.variant, fs.vertex.entry);
    const targets = fs.color_targets.map((t) => {
      if (!t.formats.includes(format)) {
        throw new Error(`${variant}: colour target ${t.location} takes ${t.formats.join(', ')}, not ${format}`);
      }
      const blend = t.blend && {
        color: blendComponent(t.blend.color),
        alpha: blendComponent(t.blend.alpha),
      };
      return { format, blend };
    });
    const groups = groupLayouts(device, variant, [vs, fs]);
    const primitive = fs.primitive ?? vs.primitive;
    const pipeline = device.createRenderPipeline({
      label: variant,
      layout: device.createPipelineLayout({ bindGroupLayouts: groups.map((g) => g.layout) }),
      vertex: {
        module: device.createShaderModule({ label: fs.vertex.variant, code: exp.wgsl(vs) }),
        entryPoint: vs.name,
        buffers: (vs.vertex_buffers ?? []).map((b) => ({
          arrayStride: b.array_stride,
          stepMode: b.step_mode,
          attributes: b.attributes.map((a) => ({
            format: a.format,
            offset: a.offset,
            shaderLocation: a.shader_location,
          })),
        })),
      },
      fragment: {
        module: device.createShaderModule({ label: variant, code: exp.wgsl(fs) }),
        entryPoint: entry,
        targets,
      },
      primitive: {
        topology: primitive.topology,
        frontFace: primitive.front_face,
        cullMode: primitive.cull_mode,
      },
    });
    return new Pass(variant, fs, groups, pipeline);
  }

  constructor(variant, entry, groups, pipeline) {
    this.variant = variant;
    this.entry = entry;
    this.groups = groups;
    this.pipeline = pipeline;
  }

  /// Bind groups with the resource `resource(binding)` returns for every binding of
  /// the pass (a GPUBindingResource: a sampler, a texture view or `{ buffer }`).
  bindGroups(device, resource) {
    return this.groups.map((g) =>
      device.createBindGroup({
        label: `${this.variant} group ${g.group}`,
        layout: g.layout,
        entries: g.bindings.map((b) => ({ binding: b.binding, resource: resource(b) })),
      }),
    );
  }

  /// Workgroups covering `grid` invocations with the manifest's workgroup size.
  workgroups(grid) {
    return grid.map((n, i) => Math.ceil(n / this.entry.workgroup_size[i]));
  }
}

function blendComponent(c) {
  return { operation: c.operation, srcFactor: c.src_factor, dstFactor: c.dst_factor };
}

// ------------------------------------------------------------------ data ---

/// An IEEE half (as a 16-bit integer) as a number.
export function halfToFloat(h) {
  const sign = h & 0x8000 ? -1 : 1;
  const exponent = (h >> 10) & 0x1f;
  const mantissa = h & 0x3ff;
  if (exponent === 0) return sign * mantissa * 2 ** -24;
  if (exponent === 31) return mantissa ? NaN : sign * Infinity;
  return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
}

/// Reads an rgba16float or r32float / rgba32float texture back as float32 values,
/// texel after texel (x fastest, then y, then layer or z).
export async function readTexture(device, texture) {
  const texelBytes = { rgba16float: 8, r32float: 4, rgba32float: 16 }[texture.format];
  if (!texelBytes) throw new Error(`cannot read ${texture.format}`);
  const [w, h, d] = [texture.width, texture.height, texture.depthOrArrayLayers];
  const bytesPerRow = Math.ceil((w * texelBytes) / 256) * 256;
  const buffer = device.createBuffer({
    size: bytesPerRow * h * d,
    usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ,
  });
  const encoder = device.createCommandEncoder();
  encoder.copyTextureToBuffer(
    { texture },
    { buffer, bytesPerRow, rowsPerImage: h },
    [w, h, d],
  );
  device.queue.submit([encoder.finish()]);
  await buffer.mapAsync(GPUMapMode.READ);
  const raw = new DataView(buffer.getMappedRange());
  const channels = texelBytes === 8 ? 4 : texelBytes / 4;
  const out = new Float32Array(w * h * d * channels);
  let k = 0;
  for (let z = 0; z < d; z++) {
    for (let y = 0; y < h; y++) {
      const row = (z * h + y) * bytesPerRow;
      for (let i = 0; i < w * channels; i++) {
        out[k++] =
          texelBytes === 8
            ? halfToFloat(raw.getUint16(row + 2 * i, true))
            : raw.getFloat32(row + 4 * i, true);
      }
    }
  }
  buffer.unmap();
  buffer.destroy();
  return out;
}
