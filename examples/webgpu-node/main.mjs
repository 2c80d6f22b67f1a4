// One frame of volfog's froxel fog in a WebGPU renderer written in JavaScript, from an
// export folder and a scene file: inject (light and density into the scattering
// volume), scan (front-to-back integration) and apply (fog over the lit image).
//
//   node main.mjs --export DIR --scene scene.json --out DIR [--backend opengl]
//
// DIR is written by `volfog export --target wgsl`. The scene file gives, by binding
// name, the value of every uniform and storage buffer (objects with the manifest's
// struct member names), the textures the renderer owns (shadow map ESM, scene depth)
// as raw little-endian float32 files, the variants to run, the volume and image
// sizes. The output folder receives scattering.f32, integrated.f32 and image.f32
// (float32 rgba, x fastest) and report.json. See README.md.

import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { parseArgs } from 'node:util';

import { Pass, VolfogExport, bufferBytes, openDevice, readTexture } from './volfog_host.mjs';

const { values: args } = parseArgs({
  options: {
    export: { type: 'string' },
    scene: { type: 'string' },
    out: { type: 'string' },
    backend: { type: 'string', default: 'opengl' },
  },
});
if (!args.export || !args.scene || !args.out) {
  console.error('usage: node main.mjs --export DIR --scene scene.json --out DIR [--backend opengl]');
  process.exit(2);
}

const scene = JSON.parse(readFileSync(args.scene, 'utf8'));
const sceneDir = dirname(resolve(args.scene));
const exp = new VolfogExport(args.export);
const { gpu, adapter, device } = await openDevice(args.backend);

// The volumes the passes hand to each other, by binding name: inject writes
// `scattering`, scan reads it and writes `integrated`, apply reads `fog_integrated`.
const [vx, vy, vz] = scene.volume_size;
const volume = (label) =>
  device.createTexture({
    label,
    size: [vx, vy, vz],
    dimension: '3d',
    format: 'rgba16float',
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.STORAGE_BINDING | GPUTextureUsage.COPY_SRC,
  });
const scattering = volume('scattering');
const integrated = volume('integrated');
const volumes = { scattering, integrated, fog_integrated: integrated };

// The renderer's own textures, from the scene file.
const textures = {};
for (const [name, t] of Object.entries(scene.textures)) {
  const [w, h, layers] = t.size;
  const texture = device.createTexture({
    label: name,
    size: [w, h, layers],
    format: t.format,
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
    textureBindingViewDimension: t.view_dimension,
  });
  const data = readFileSync(join(sceneDir, t.file));
  device.queue.writeTexture(
    { texture },
    data,
    { bytesPerRow: w * 4 * (t.format === 'rgba32float' ? 4 : 1), rowsPerImage: h },
    [w, h, layers],
  );
  textures[name] = texture;
}

// Samplers as the manifest's usage text asks: filtering ones linear, clamp to edge.
const samplers = {
  filtering: device.createSampler({ magFilter: 'linear', minFilter: 'linear' }),
  'non-filtering': device.createSampler({}),
  comparison: device.createSampler({ compare: 'less' }),
};

// Every binding of a pass gets its resource by name.
function resourceFor(pass) {
  return (binding) => {
    const r = binding.resource;
    if (r.kind === 'buffer') {
      const value = scene.values[binding.name];
      if (value === undefined) throw new Error(`${pass.variant}: no value for buffer ${binding.name}`);
      const bytes = bufferBytes(pass.entry, binding, value);
      const buffer = device.createBuffer({
        label: binding.name,
        size: bytes.byteLength,
        usage: (r.type === 'uniform' ? GPUBufferUsage.UNIFORM : GPUBufferUsage.STORAGE) | GPUBufferUsage.COPY_DST,
      });
      device.queue.writeBuffer(buffer, 0, bytes);
      return { buffer };
    }
    if (r.kind === 'sampler') return samplers[r.type];
    const texture = volumes[binding.name] ?? textures[binding.name];
    if (!texture) throw new Error(`${pass.variant}: no texture for ${binding.name}`);
    return texture.createView({ dimension: r.view_dimension });
  };
}

const v = scene.variants;
const inject = Pass.compute(device, exp, v.inject, 'inject');
const scan = Pass.compute(device, exp, v.scan, 'scan');
const apply = Pass.render(device, exp, v.apply, 'apply_fs', scene.image.format);

const encoder = device.createCommandEncoder();
for (const [pass, grid] of [
  [inject, [vx, vy, vz]],
  [scan, [vx, vy, 1]],
]) {
  const c = encoder.beginComputePass({ label: pass.variant });
  c.setPipeline(pass.pipeline);
  pass.bindGroups(device, resourceFor(pass)).forEach((g, i) => c.setBindGroup(i, g));
  c.dispatchWorkgroups(...pass.workgroups(grid));
  c.end();
}
const [w, h] = scene.image.size;
const image = device.createTexture({
  label: 'lit image',
  size: [w, h],
  format: scene.image.format,
  usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC,
});
const [r, g, b, a] = scene.image.clear;
const rp = encoder.beginRenderPass({
  label: apply.variant,
  colorAttachments: [
    { view: image.createView(), loadOp: 'clear', clearValue: { r, g, b, a }, storeOp: 'store' },
  ],
});
rp.setPipeline(apply.pipeline);
apply.bindGroups(device, resourceFor(apply)).forEach((grp, i) => rp.setBindGroup(i, grp));
rp.draw(3);
rp.end();
device.queue.submit([encoder.finish()]);

mkdirSync(args.out, { recursive: true });
const outputs = { scattering, integrated, image };
for (const [name, texture] of Object.entries(outputs)) {
  const data = await readTexture(device, texture);
  writeFileSync(join(args.out, `${name}.f32`), Buffer.from(data.buffer));
}
const info = adapter.info ?? {};
writeFileSync(
  join(args.out, 'report.json'),
  JSON.stringify({
    adapter: [info.description, info.device].filter((x) => x).join(', ') || 'unknown',
    backend: args.backend,
    passes: [inject.variant, scan.variant, apply.variant],
  }),
);
console.log(`volfog frame on ${args.backend}: ${Object.keys(outputs).join(', ')} written to ${args.out}`);
device.destroy();
void gpu;
