// The HTML report (src/report/html_report.h) in a real browser: Debian's chromium, headless, driven
// by playwright-core from tools/node_modules (which downloads no browser).
//
//   node tests/report_browser_test.mjs HYBRIDBENCH WORKDIR
//
// Sweeps tests/fixtures/report-browser.json on the device present (lavapipe here) into
// WORKDIR/sweep, writes a base for a comparison (the same results with one variant's frames made
// faster, so that B is slower there), and `hybridbench report --compare` into WORKDIR/compare/.
// Then loads each page by file:// with every other request blocked, and asserts: no console error,
// page error or failed request; every <img> loaded; the Pareto plot has one point per variant of
// results.json; opening a variant by its summary shows its images, loaded; the comparison's B/A
// plot has one point per row of `hybridbench compare`; a full-page screenshot is not blank. The
// screenshots are kept in WORKDIR (their paths printed) for a person to look at.
import { execFileSync } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const [hb, workArg] = process.argv.slice(2);
if (!hb || !workArg) {
  console.error('usage: node tests/report_browser_test.mjs HYBRIDBENCH WORKDIR');
  process.exit(2);
}
const work = path.resolve(workArg);
const chromiumPath = '/usr/bin/chromium';
let chromium;
try {
  chromium = createRequire(path.join(repo, 'tools', 'package.json'))('playwright-core').chromium;
} catch (e) {
  console.error(`report_browser_test: playwright-core is not in tools/node_modules (${e.message}); run scripts/setup.sh`);
  process.exit(1);
}
if (!fs.existsSync(chromiumPath)) {
  console.error(`report_browser_test: no ${chromiumPath}; install Debian's chromium (scripts/setup.sh)`);
  process.exit(1);
}

const failures = [];
const check = (ok, what) => {
  if (!ok) failures.push(what);
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
};
const started = Date.now();
const seconds = () => ((Date.now() - started) / 1000).toFixed(1);

// --- the files: a real sweep, a base, the two pages ----------------------------------------------
fs.rmSync(work, { recursive: true, force: true });
fs.mkdirSync(path.join(work, 'compare'), { recursive: true });
const sweep = path.join(work, 'sweep');
execFileSync(hb, ['sweep', path.join(repo, 'tests/fixtures/report-browser.json'), '--out', sweep], {
  stdio: ['ignore', 'ignore', 'inherit'],
});
console.log(`swept in ${seconds()} s`);
const resultsPath = path.join(sweep, 'results.json');
const results = JSON.parse(fs.readFileSync(resultsPath, 'utf8'));
const names = results.runs.map((r) => r.name);
check(results.runs.every((r) => r.status === 'ok'), `every variant of the sweep is ok (${names.length})`);

// A: the same results with the first variant's frames 20 % faster, so that B/A is about 1.25 there.
const base = structuredClone(results);
const fm = base.runs[0].frame_ms;
fm.samples = fm.samples.map((v) => 0.8 * v);
for (const k of ['median', 'mean', 'min', 'max', 'p95']) fm[k] *= 0.8;
const basePath = path.join(work, 'base.json');
fs.writeFileSync(basePath, JSON.stringify(base));
const comparePage = path.join(work, 'compare', 'report.html');
execFileSync(hb, ['report', resultsPath, '--compare', basePath, '--out', comparePage], { stdio: 'inherit' });
// compare exits 1 on a regression: its JSON is what we want either way.
let compareJson;
try {
  compareJson = execFileSync(hb, ['compare', basePath, resultsPath, '--format', 'json'], { encoding: 'utf8' });
} catch (e) {
  compareJson = e.stdout;
}
const compareRows = JSON.parse(compareJson).rows.length;

// The images the sweep wrote, per variant folder: what each page must show.
const pngsOnDisk = fs
  .readdirSync(sweep, { withFileTypes: true })
  .filter((d) => d.isDirectory())
  .flatMap((d) => fs.readdirSync(path.join(sweep, d.name)).filter((f) => f.endsWith('.png')));

// --- the browser ---------------------------------------------------------------------------------
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'hb-report-chromium-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: chromiumPath,
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  viewport: { width: 1280, height: 900 },
});

// A screenshot is not blank when it has many colours and is not nearly all one: a blank page is
// one colour (white), an error page a few dozen; a page with a plot, tables and a variant's
// rendered images has thousands (measured: printed below).
async function screenshotFigures(png) {
  const page = await context.newPage();
  const figures = await page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const canvas = document.createElement('canvas');
    canvas.width = img.naturalWidth;
    canvas.height = img.naturalHeight;
    const g = canvas.getContext('2d');
    g.drawImage(img, 0, 0);
    const px = g.getImageData(0, 0, canvas.width, canvas.height).data;
    const colours = new Set();
    let notWhite = 0;
    for (let i = 0; i < px.length; i += 4) {
      colours.add((px[i] << 16) | (px[i + 1] << 8) | px[i + 2]);
      if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) notWhite++;
    }
    return { width: canvas.width, height: canvas.height, colours: colours.size, notWhite: notWhite / (px.length / 4) };
  }, png.toString('base64'));
  await page.close();
  return figures;
}

async function checkPage(file, label, extra) {
  const page = await context.newPage();
  const problems = [];
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`console error: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => problems.push(`request failed: ${r.url()} (${r.failure()?.errorText})`));
  await page.route('**/*', (route) => {
    const url = route.request().url();
    if (url.startsWith('file://')) return route.continue();
    problems.push(`request outside the page's files: ${url}`);
    return route.abort();
  });
  await page.goto(pathToFileURL(file).href, { waitUntil: 'load' });

  // The Pareto plot: one point per variant.
  const points = await page.$$eval('#pareto circle[data-variant]', (cs) => cs.map((c) => c.getAttribute('data-variant')));
  check(points.length === names.length && names.every((n) => points.includes(n)),
    `${label}: the Pareto plot has one point per variant (${points.length} points, ${names.length} variants)`);

  // Open the last variant (its name has < > & " in it) by clicking its summary: its images show.
  const last = page.locator('details.variant').last();
  await last.locator('summary').click();
  const shown = last.locator('img');
  const n = await shown.count();
  for (let i = 0; i < n; i++) await shown.nth(i).scrollIntoViewIfNeeded();
  const loadedShown = await shown.evaluateAll(async (imgs) => {
    await Promise.all(imgs.map((i) => i.decode().catch(() => {})));
    return imgs.filter((i) => i.complete && i.naturalWidth > 0 && i.getBoundingClientRect().width > 0).length;
  });
  const lastSummary = (await last.locator('summary b').textContent()) ?? '';
  check(n > 0 && loadedShown === n && lastSummary === names[names.length - 1],
    `${label}: clicking "${lastSummary}" shows its ${n} images, ${loadedShown} loaded and visible`);
  const shot = path.join(work, `${label}-variant.png`);
  await last.screenshot({ path: shot });
  console.log(`screenshot: ${shot}`);

  // Every image of every variant: open them all, bring each into view (they load lazily).
  await page.$$eval('details.variant', (ds) => ds.forEach((d) => (d.open = true)));
  const all = page.locator('img');
  const total = await all.count();
  for (let i = 0; i < total; i++) await all.nth(i).scrollIntoViewIfNeeded();
  const broken = await all.evaluateAll(async (imgs) => {
    await Promise.all(imgs.map((i) => i.decode().catch(() => {})));
    return imgs.filter((i) => !(i.complete && i.naturalWidth > 0)).map((i) => i.getAttribute('src'));
  });
  check(total === pngsOnDisk.length && broken.length === 0,
    `${label}: all ${total} images loaded (${pngsOnDisk.length} PNGs in the variant folders)` +
      (broken.length ? `; not loaded: ${broken.join(', ')}` : ''));

  if (extra) await extra(page);

  await page.evaluate(() => window.scrollTo(0, 0));
  const full = path.join(work, `${label}.png`);
  const png = await page.screenshot({ path: full, fullPage: true });
  console.log(`screenshot: ${full}`);
  const f = await screenshotFigures(png);
  check(f.colours > 1000 && f.notWhite > 0.05,
    `${label}: the screenshot is not blank (${f.width}x${f.height}, ${f.colours} colours, ` +
      `${(100 * f.notWhite).toFixed(1)} % not white)`);
  check(problems.length === 0, `${label}: no console errors, page errors or outside requests` +
    (problems.length ? `: ${problems.join('; ')}` : ''));
  await page.close();
}

try {
  await checkPage(path.join(sweep, 'report.html'), 'report');
  await checkPage(comparePage, 'compare', async (page) => {
    const ratioPoints = await page.locator('#ratios circle').count();
    check(ratioPoints === compareRows, `compare: the B/A plot has one point per compared row (${ratioPoints} of ${compareRows})`);
    const slower = await page.locator(`#ratios g[data-pass="frame"] circle`).first().getAttribute('fill');
    check(slower === '#d62728' || slower === '#e0a800',
      `compare: the first variant's frame, 25 % slower in B, is drawn slower or too noisy (${slower})`);
    check((await page.locator('#compare table').count()) === 1, 'compare: the comparison table is there');
  });
} finally {
  await context.close();
  fs.rmSync(profile, { recursive: true, force: true });
}
console.log(`${failures.length ? 'FAILED' : 'passed'} in ${seconds()} s`);
process.exit(failures.length ? 1 : 0);
