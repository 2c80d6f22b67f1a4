// The page: WebGPU runs the froxel pipeline from wasm (pkg/, built by wasm-bindgen).
// `?check=WxH` runs the browser test's fixed frame instead of the demo and posts what
// it read back to the server that served the page.

const query = new URLSearchParams(location.search);
const checking = query.has('check');

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
  const [w, h] = query.get('check').split('x').map(Number);
  return [w || 320, h || 180];
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

// Frame time: the mean of the last 30 frames' intervals.
function frameLoop(draw) {
  const stats = document.getElementById('stats');
  const times = [];
  const start = performance.now();
  const tick = (now) => {
    if (failed) return;
    times.push(now);
    if (times.length > 31) times.shift();
    if (times.length > 1) {
      const ms = (times[times.length - 1] - times[0]) / (times.length - 1);
      stats.textContent = `${ms.toFixed(1)} ms/frame (${(1000 / ms).toFixed(1)} fps)`;
    }
    draw((now - start) / 1000);
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}

async function webgpu() {
  const wasm = await import('./pkg/volfog_web.js');
  await wasm.default();
  if (checking) {
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
  frameLoop((t) => demo.frame(t));
}

if (!('gpu' in navigator) || (await navigator.gpu.requestAdapter()) === null) {
  window.volfogError('this browser offers no WebGPU adapter: volfog\'s froxel fog needs WebGPU');
} else {
  await webgpu();
}
