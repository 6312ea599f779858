// Drive Debian's Firefox ESR over WebDriver BiDi with puppeteer-core (pinned in package.json; no browser
// is downloaded): open a page, then evaluate the page expressions given on stdin, in order.
//
//   echo '{"url": ..., "steps": [{"poll": "<js>", "timeout_s": 300}, {"eval": "<js>"}, ...]}' |
//     node tests/browser/firefox_lite.mjs /usr/bin/firefox-esr
//
// Prints one JSON line: {"results": [the value of each step], "seconds": [the time each step took],
// "browser": the version}.  A poll that is not true within its timeout fails the run (exit 1).
import puppeteer from "puppeteer-core";

const chunks = [];
for await (const chunk of process.stdin) chunks.push(chunk);
const spec = JSON.parse(Buffer.concat(chunks).toString("utf8"));
const browser = await puppeteer.launch({
  browser: "firefox",
  executablePath: process.argv[2],
  headless: true,
  protocol: "webDriverBiDi",
  extraPrefsFirefox: { "network.proxy.type": 0 },
});
const out = { results: [], seconds: [], browser: await browser.version() };
let failed = null;
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 900 });
  await page.goto(spec.url, { waitUntil: "domcontentloaded", timeout: 120000 });
  for (const step of spec.steps) {
    const start = Date.now();
    if (step.poll) {
      const deadline = start + step.timeout_s * 1000;
      let value = false;
      while (Date.now() < deadline) {
        try { value = await page.evaluate(step.poll); } catch (error) { value = false; }
        if (value) break;
        await new Promise((resolve) => setTimeout(resolve, 500));
      }
      out.results.push(value);
      if (!value) { failed = `not true within ${step.timeout_s} s: ${step.poll.slice(0, 200)}`; break; }
    } else {
      out.results.push(await page.evaluate(step.eval));
    }
    out.seconds.push((Date.now() - start) / 1000);
  }
} catch (error) {
  failed = String(error);
} finally {
  await browser.close();
}
if (failed) out.error = failed;
console.log(JSON.stringify(out));
process.exit(failed ? 1 : 0);
