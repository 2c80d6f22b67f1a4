// The page: WebGPU runs the froxel pipeline from wasm (pkg/, built by wasm-bindgen);
// without WebGPU the WebGL2 tier draws the closed-form fog (webgl2.js). `?check=WxH`
// runs the browser test's fixed frame instead of the demo and posts what it read back
// to the server that served the page; `?frames=N` runs the demo and posts its frame
// time and the canvas's statistics after N frames; `?tier=webgl2` asks for the WebGL2
// tier.

const query = new URLSearchParams(location.search);
// A test is watching: errors and results are posted to the server.
const checking = query.has('check') || query.has('frames');
const checkFrame = query.has('check');

async function post(path, body) {
  await fetch(path, { method: 'POST', body });
}

// Every failure is shown, and posted to the server when checking.
let failed = false;
window.volfogError = (message) => {
  failed = true;
  document.getElementById('error').textContent += `${message}\n`;
  console.error(`volfog: ${message}`);
  if (checking) post('/report/error', String(message));
};
window.addEventListener('error', (e) => window.volfogError(e.error?.stack ?? e.message));
window.addEventListener('unhandledrejection', (e) => window.volfogError(e.reason?.stack ?? String(e.reason)));

function checkSize() {
  // Whatever the query says reaches the wasm module, which checks it.
  const [w, h] = query.get('check').split('x').map(Number);
  return [w, h];
}

function sliderPanel(sliders, set) {
  const panel = document.getElementById('panel');
  for (const s of sliders) {
    const label = document.createElement('label');
    const input = document.createElement('input');
    Object.assign(input, { type: 'range', min: s.min, max: s.max, step: (s.max - s.min) / 200, value: s.value });
    const shown = document.createElement('span');
    const update = () => { shown.textContent = Number(input.value).toFixed(3); set(s.name, Number(input.value)); };
    input.addEventListener('input', update);
    label.append(s.name, input, shown);
    panel.append(label);
    update();
  }
}

// The canvas's mean and standard deviation of 8-bit values, read through a 2D canvas.
function canvasStatistics(canvas) {
  const probe = document.createElement('canvas');
  Object.assign(probe, { width: 96, height: 54 });
  const ctx = probe.getContext('2d');
  ctx.drawImage(canvas, 0, 0, probe.width, probe.height);
  const data = ctx.getImageData(0, 0, probe.width, probe.height).data;
  let sum = 0;
  let squares = 0;
  let n = 0;
  for (let i = 0; i < data.length; i += 4) {
    for (let c = 0; c < 3; c++) {
      sum += data[i + c];
      squares += data[i + c] * data[i + c];
      n += 1;
    }
  }
  const mean = sum / n;
  return { mean, deviation: Math.sqrt(Math.max(squares / n - mean * mean, 0)) };
}

// Frame time: the mean of the last 30 frames' intervals. With `?frames=N` the page
// posts the frame time and the canvas's statistics after N frames.
function frameLoop(tier, adapter, draw) {
  const canvas = document.getElementById('fog');
  const stats = document.getElementById('stats');
  const times = [];
  const start = performance.now();
  const report = Number(query.get('frames') ?? 0);
  let count = 0;
  const tick = (now) => {
    if (failed) return;
    times.push(now);
    if (times.length > 31) times.shift();
    const ms = times.length > 1 ? (times[times.length - 1] - times[0]) / (times.length - 1) : NaN;
    if (times.length > 1) stats.textContent = `${ms.toFixed(1)} ms/frame (${(1000 / ms).toFixed(1)} fps)`;
    draw((now - start) / 1000);
    count += 1;
    if (count === report) {
      const size = [canvas.width, canvas.height];
      post('/report/done', JSON.stringify({ tier, adapter, size, frames: count, ms, ...canvasStatistics(canvas) }));
    }
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}

async function webgpu() {
  const wasm = await import('./pkg/volfog_web.js');
  await wasm.default();
  if (checkFrame) {
    const [w, h] = checkSize();
    const t0 = performance.now();
    const result = await wasm.check(w, h);
    const ms = performance.now() - t0;
    await post('/report/integrated', result.integrated);
    await post('/report/image', result.image);
    await post('/report/done', JSON.stringify({ tier: 'webgpu', adapter: result.adapter, volume_size: result.volume_size, size: [w, h], ms }));
    return;
  }
  const canvas = document.getElementById('fog');
  const demo = await wasm.Demo.create(canvas);
  document.getElementById('tier').textContent = `WebGPU: ${demo.adapter()}`;
  sliderPanel(wasm.sliders(), (name, value) => demo.set(name, value));
  frameLoop('webgpu', demo.adapter(), (t) => demo.frame(t));
}

async function webgl2() {
  const wasm = await import('./pkg/volfog_web.js');
  await wasm.default();
  const tier = await import('./webgl2.js');
  if (checkFrame) {
    const [w, h] = checkSize();
    const result = await tier.check(wasm, w, h);
    await post('/report/image', result.image);
    await post('/report/done', JSON.stringify({ tier: 'webgl2', adapter: result.adapter, size: [w, h], ms: result.ms }));
    return;
  }
  const demo = await tier.Demo.create(wasm, document.getElementById('fog'));
  document.getElementById('tier').textContent = `WebGL2, analytic fog: ${demo.adapter}`;
  sliderPanel(wasm.sliders(), (name, value) => demo.set(name, value));
  frameLoop('webgl2', demo.adapter, () => demo.frame());
}

// WebGPU when the browser has an adapter, the WebGL2 tier otherwise or with
// `?tier=webgl2`.
const wanted = query.get('tier');
const hasWebGpu = 'gpu' in navigator && (await navigator.gpu.requestAdapter()) !== null;
if (wanted === 'webgl2' || !hasWebGpu) {
  await webgl2();
} else {
  await webgpu();
}
