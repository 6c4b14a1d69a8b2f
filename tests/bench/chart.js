// Line charts as SVG for the benchmark scripts (no dependencies).
// node chart.js OUT.svg "title" "x label" "y label" CSV XCOL YCOL [SERIESCOL] [log]
// One line per distinct value of SERIESCOL (or one line), points in CSV order.
const fs = require("fs");
const [out, title, xl, yl, csvPath, xc, yc, sc, scale] = process.argv.slice(2);
const lines = fs.readFileSync(csvPath, "utf8").trim().split("\n");
const head = lines[0].split(","), rows = lines.slice(1).map(l => l.split(","));
const col = name => { const i = head.indexOf(name); if (i < 0) throw new Error(`no column ${name}`); return i; };
const xi = col(xc), yi = col(yc), si = sc ? col(sc) : -1;
const series = new Map();
for (const r of rows) {
  const key = si < 0 ? yc : r[si];
  if (!series.has(key)) series.set(key, []);
  series.get(key).push([+r[xi], +r[yi]]);
}
const log = scale === "log";
const tx = v => (log ? Math.log2(v) : v);
const all = [...series.values()].flat();
const x0 = Math.min(...all.map(p => tx(p[0]))), x1 = Math.max(...all.map(p => tx(p[0])));
const y0 = Math.min(0, ...all.map(p => p[1])), y1 = Math.max(...all.map(p => p[1])) * 1.05 || 1;
const W = 640, H = 400, L = 70, R = 170, T = 40, B = 50;
const px = v => L + ((tx(v) - x0) / (x1 - x0 || 1)) * (W - L - R);
const py = v => H - B - ((v - y0) / (y1 - y0 || 1)) * (H - T - B);
const colours = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"];
let svg = `<svg xmlns="http://www.w3.org/2000/svg" width="${W}" height="${H}" font-family="sans-serif" font-size="12">\n`;
svg += `<rect width="${W}" height="${H}" fill="white"/>\n<text x="${W / 2}" y="22" text-anchor="middle" font-size="15">${title}</text>\n`;
svg += `<line x1="${L}" y1="${H - B}" x2="${W - R}" y2="${H - B}" stroke="black"/><line x1="${L}" y1="${T}" x2="${L}" y2="${H - B}" stroke="black"/>\n`;
// Every distinct x is a tick, or 10 evenly spaced ones when there are more than 20.
let ticks = [...new Set(all.map(p => p[0]))];
if (ticks.length > 20)
  ticks = [...Array(11).keys()].map(k => +(log ? 2 ** (x0 + ((x1 - x0) * k) / 10) : x0 + ((x1 - x0) * k) / 10).toPrecision(3));
for (const x of ticks)
  svg += `<text x="${px(x)}" y="${H - B + 16}" text-anchor="middle">${x}</text>\n`;
for (let k = 0; k <= 4; ++k) {
  const v = y0 + ((y1 - y0) * k) / 4;
  svg += `<text x="${L - 6}" y="${py(v) + 4}" text-anchor="end">${+v.toPrecision(3)}</text>`;
  svg += `<line x1="${L}" y1="${py(v)}" x2="${W - R}" y2="${py(v)}" stroke="#ddd"/>\n`;
}
svg += `<text x="${(L + W - R) / 2}" y="${H - 10}" text-anchor="middle">${xl}</text>\n`;
svg += `<text transform="translate(16 ${(T + H - B) / 2}) rotate(-90)" text-anchor="middle">${yl}</text>\n`;
[...series.entries()].forEach(([name, pts], i) => {
  const c = colours[i % colours.length];
  svg += `<polyline fill="none" stroke="${c}" stroke-width="2" points="${pts.map(p => `${px(p[0])},${py(p[1])}`).join(" ")}"/>\n`;
  if (pts.length <= 100) // dots only where they can be told apart
    for (const p of pts) svg += `<circle cx="${px(p[0])}" cy="${py(p[1])}" r="3" fill="${c}"/>`;
  svg += `\n<text x="${W - R + 10}" y="${T + 16 * i + 10}" fill="${c}">${name}</text>\n`;
});
fs.writeFileSync(out, svg + "</svg>\n");
