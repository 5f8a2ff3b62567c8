// A screenshot of arphys-view's page once it has drawn: Debian's Chromium, headless, driven by
// puppeteer-core, waits until the page has shown MIN frames of the overlay and drawn bodies
// in 3D (window.arphysView), then writes the PNG. Exits 1 when that does not happen in time.
//   node screenshot_page.mjs http://127.0.0.1:PORT/ OUT.png [TIMEOUT_S] [MIN]
import puppeteer from "puppeteer-core";

const [url, out, timeoutS = "40", minFrames = "5"] = process.argv.slice(2);
if (!url || !out) {
  console.error("usage: node screenshot_page.mjs URL OUT.png [TIMEOUT_S] [MIN]");
  process.exit(2);
}
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--enable-unsafe-swiftshader", "--window-size=1300,700"],
  defaultViewport: { width: 1300, height: 700 },
});
let status = 0;
try {
  const page = await browser.newPage();
  await page.goto(url);
  await page.waitForFunction(
    (min) => window.arphysView && window.arphysView.overlays >= min && window.arphysView.bodies >= 3,
    { timeout: Number(timeoutS) * 1000, polling: 200 },
    Number(minFrames));
  await page.screenshot({ path: out });
  console.log(JSON.stringify(await page.evaluate(() => ({ overlays: window.arphysView.overlays,
    worldUpdates: window.arphysView.worldUpdates, bodies: window.arphysView.bodies }))));
} catch (e) {
  console.error(`screenshot_page: ${e.message}`);
  status = 1;
} finally {
  await browser.close();
}
process.exit(status);
