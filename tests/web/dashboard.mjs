// The dashboard in a real browser (Debian's chromium, driven by Playwright), against a real sphd
// running real jobs: the page lists the jobs, a running job's plot gains points, the pause button
// pauses it (seen through sphctl), a `set` from the page changes the value `query` returns, and a
// 3D job's particles are drawn. Screenshots of the jobs page and of the 3D view go to OUT.
// usage: node dashboard.mjs URL SPHCTL ENDPOINT OUT JOB2D JOB3D   (exit 0 when every check holds)
import { chromium } from "playwright-core";
import { execFileSync } from "node:child_process";

const [url, sphctl, endpoint, out, job2d, job3d] = process.argv.slice(2);
let failed = 0, passed = 0;
function check(ok, what, detail) {
  if (ok) passed++;
  else {
    failed++;
    console.log(`FAIL: ${what}` + (detail !== undefined ? `: ${JSON.stringify(detail)}` : ""));
  }
}
function ctl(...args) {
  return JSON.parse(execFileSync(sphctl, ["--endpoint", endpoint, "--json", ...args],
    { encoding: "utf8" }));
}
const sleep = (ms) => new Promise((ok) => setTimeout(ok, ms));
async function until(what, f, ms = 20000) {
  const t0 = Date.now();
  for (;;) {
    const v = await f();
    if (v) return v;
    if (Date.now() - t0 > ms) return v;
    await sleep(100);
  }
}

const browser = await chromium.launch({
  executablePath: process.env.SPH_CHROMIUM || "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 960 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  await page.goto(url);

  const listed = await until("jobs listed", async () =>
    (await page.locator(`tr[data-job="${job2d}"]`).count()) > 0 &&
    (await page.locator(`tr[data-job="${job3d}"]`).count()) > 0);
  check(listed, "the page lists both jobs");

  // a running job's plot gains points from the event stream
  await page.click(`tr[data-job="${job2d}"]`);
  await until("a plot", async () => (await page.evaluate(() => window.sphdDash.points())) > 0);
  const p0 = await page.evaluate(() => window.sphdDash.points());
  await sleep(2500);
  const p1 = await page.evaluate(() => window.sphdDash.points());
  check(p1 > p0 && p0 > 0, `the plot gains points as the job runs (${p0} -> ${p1})`, [p0, p1]);
  check(await page.locator("#conn.live").count() === 1, "the event stream is live");
  await page.screenshot({ path: `${out}/dashboard-jobs.png` });

  // the pause button pauses it: seen through sphctl
  await page.click('button[data-op="pause"]');
  const paused = await until("paused", async () => ctl("status", job2d).state === "paused");
  check(paused, "the pause button pauses the job (sphctl status)", ctl("status", job2d).state);

  // a set from the page: query returns the new value
  await page.fill("#set-text", "physics.viscosity.alpha=0.07");
  await page.click("#set-go");
  const alpha = await until("set", async () => {
    const q = ctl("query", job2d);
    return q.steering && q.steering.values["physics.viscosity.alpha"] === 0.07;
  });
  check(alpha, "a set from the page changes the value query returns",
        ctl("query", job2d).steering);
  const msg = await page.textContent("#message");
  check(/changed/.test(msg), "the page says it changed", msg);

  // a 3D job's particles
  await page.click(`tr[data-job="${job3d}"]`);
  const drawn = await until("3D drawn", async () =>
    +(await page.getAttribute("#particles", "data-drawn") || 0) > 0);
  check(drawn, "the 3D job's particles are drawn");
  await page.evaluate(() => document.getElementById("particles").scrollIntoView());
  await page.locator(".panes").screenshot({ path: `${out}/dashboard-3d.png` });
  check(errors.length === 0, "no script errors in the page", errors);
} finally {
  await browser.close();
}
console.log(`dashboard (browser): ${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
