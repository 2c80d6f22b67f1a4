// The WebGL2 tier, for browsers without WebGPU: the closed-form fog (Wenzel height fog
// with its sun lobe, two fog volumes, the Nishita sky, the fog continuing to the sky)
// in one fragment shader that includes volfog's GLSL ES 3.00 snippet. The uniform
// block comes from the wasm module (`analytic_block`, volfog-web's analytic.rs), whose
// CPU mirror of this shader the browser test compares the image with.

const SNIPPET = 'shaders/glsl/include/volfog_all.es.glsl';

const VERTEX = `#version 300 es
void main() {
  vec2 uv = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}
`;

const SCENE = `
layout(std140) uniform Scene {
  mat4 world_from_clip;
  vec4 eye;     // xyz camera (m), w how far the fog reaches towards the sky (m)
  vec4 ground;  // rgb radiance leaving the ground per unit albedo
  volfog_HeightFog fog;
  volfog_FogVolume volumes[2];
  volfog_SkyAtmosphere atmosphere;
} scene;
uniform vec2 size;
uniform int display;  // 1: exposure, tone curve and sRGB for the canvas
layout(location = 0) out vec4 color;

float ground_albedo(vec3 p) {
  float cell = floor(p.x * 0.5) + floor(p.z * 0.5);
  return mod(cell, 2.0) < 0.5 ? 0.25 : 0.4;
}

void main() {
  vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
  vec4 far = scene.world_from_clip * vec4(ndc, 1.0, 1.0);
  vec3 eye = scene.eye.xyz;
  vec3 dir = normalize(far.xyz / far.w - eye);
  vec3 point;
  vec3 surface;
  if (dir.y < -1e-4) {
    point = eye + dir * min(eye.y / -dir.y, scene.eye.w);
    surface = scene.ground.rgb * ground_albedo(point);
  } else {
    point = eye + dir * scene.eye.w;
    volfog_SkyScattering sky = volfog_sky_single_scattering(scene.atmosphere, dir);
    surface = volfog_sky_radiance(sky, dot(dir, scene.atmosphere.sun_direction), scene.atmosphere);
  }
  vec4 fog = volfog_height_fog(scene.fog, eye, point - eye);
  fog = volfog_fog_over(volfog_fog_volume(scene.volumes[1], eye, point), fog);
  fog = volfog_fog_over(volfog_fog_volume(scene.volumes[0], eye, point), fog);
  vec3 c = surface * fog.a + fog.rgb;
  color = display == 1 ? vec4(pow(1.0 - exp(-1.5 * max(c, vec3(0.0))), vec3(1.0 / 2.2)), 1.0)
                       : vec4(c, 1.0);
}
`;

function compile(gl, type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new Error(`WebGL2 shader: ${gl.getShaderInfoLog(shader)}`);
  }
  return shader;
}

function renderer(gl) {
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}

// The program, its uniform buffer, and a draw at the current size.
async function program(gl) {
  const snippet = await (await fetch(SNIPPET)).text();
  const fragment = `#version 300 es\nprecision highp float;\nprecision highp int;\n${snippet}\n${SCENE}`;
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, VERTEX));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, fragment));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
    throw new Error(`WebGL2 program: ${gl.getProgramInfoLog(p)}`);
  }
  const block = gl.getUniformBlockIndex(p, 'Scene');
  gl.uniformBlockBinding(p, block, 0);
  const ubo = gl.createBuffer();
  const needed = gl.getActiveUniformBlockParameter(p, block, gl.UNIFORM_BLOCK_DATA_SIZE);
  return {
    draw(bytes, width, height, display) {
      if (bytes.byteLength < needed) {
        throw new Error(`the Scene block needs ${needed} bytes, the wasm module gave ${bytes.byteLength}`);
      }
      gl.useProgram(p);
      gl.bindBuffer(gl.UNIFORM_BUFFER, ubo);
      gl.bufferData(gl.UNIFORM_BUFFER, bytes, gl.DYNAMIC_DRAW);
      gl.bindBufferBase(gl.UNIFORM_BUFFER, 0, ubo);
      gl.uniform2f(gl.getUniformLocation(p, 'size'), width, height);
      gl.uniform1i(gl.getUniformLocation(p, 'display'), display ? 1 : 0);
      gl.viewport(0, 0, width, height);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      const error = gl.getError();
      if (error !== gl.NO_ERROR) throw new Error(`WebGL2 error 0x${error.toString(16)}`);
    },
  };
}

function context(canvas) {
  const gl = canvas.getContext('webgl2', { antialias: false });
  if (!gl) throw new Error('this browser offers neither WebGPU nor WebGL2');
  return gl;
}

// The browser test's frame: the default sliders at w x h into an RGBA32F target, read
// back (rows from the bottom).
export async function check(wasm, w, h) {
  const canvas = document.createElement('canvas');
  Object.assign(canvas, { width: w, height: h });
  const gl = context(canvas);
  if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('no EXT_color_buffer_float');
  const t0 = performance.now();
  const draw = await program(gl);
  const target = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, target);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, w, h);
  const fbo = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
  const defaults = Object.fromEntries(wasm.sliders().map((s) => [s.name, s.value]));
  draw.draw(wasm.analytic_block(w, h, defaults.density, defaults.phase_g, defaults.sun_elevation), w, h, false);
  const image = new Float32Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, image);
  return { image, adapter: renderer(gl), ms: performance.now() - t0 };
}

// The demo in a canvas: the sliders' values each frame.
export class Demo {
  static async create(wasm, canvas) {
    const demo = new Demo();
    demo.wasm = wasm;
    demo.canvas = canvas;
    demo.gl = context(canvas);
    demo.adapter = renderer(demo.gl);
    demo.draw = await program(demo.gl);
    demo.values = Object.fromEntries(wasm.sliders().map((s) => [s.name, s.value]));
    return demo;
  }

  set(name, value) {
    if (!(name in this.values)) throw new Error(`no slider named ${name}`);
    this.values[name] = value;
  }

  frame() {
    const { width, height } = this.canvas;
    const v = this.values;
    this.draw.draw(this.wasm.analytic_block(width, height, v.density, v.phase_g, v.sun_elevation), width, height, true);
  }
}
