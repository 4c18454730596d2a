// The numbers of a plot's axis: ticks at 1, 2 or 5 × 10^k, bounds on ticks,
// and labels with the digits the step needs (no more, no less).

// The smallest span shown, relative to the values' size: a quantity constant
// to round-off (an energy drifting by 1e-13 J) is drawn flat, not magnified.
const relativeSpan = 1e-6;

// The smallest of 1, 2 or 5 × 10^k not below `value` (> 0).
export function roundUp(value) {
  const power = 10 ** Math.floor(Math.log10(value));
  return [1, 2, 5, 10].map((m) => m * power).find((s) => s >= value * (1 - 1e-12));
}

// Ticks covering [lo, hi], about `count` intervals: { lo, hi, step, ticks },
// lo and hi rounded out to ticks.
export function niceAxis(lo, hi, count = 5) {
  if (!isFinite(lo) || !isFinite(hi)) { lo = 0; hi = 1; }
  if (lo > hi) [lo, hi] = [hi, lo];
  const size = Math.max(Math.abs(lo), Math.abs(hi));
  const least = size > 0 ? size * relativeSpan : 1;
  if (hi - lo < least) {
    const middle = (lo + hi) / 2;
    lo = middle - least / 2;
    hi = middle + least / 2;
  }
  const step = roundUp((hi - lo) / Math.max(1, count));
  const first = Math.floor(lo / step + 1e-9), last = Math.ceil(hi / step - 1e-9);
  const ticks = [];
  for (let k = first; k <= last; ++k) ticks.push(k * step);
  return { lo: first * step, hi: last * step, step, ticks };
}

// Labels of ticks `step` apart: fixed decimals for everyday sizes, else
// exponents; each with the digits that tell neighbouring ticks apart.
export function tickLabels(ticks, step) {
  const size = Math.max(...ticks.map(Math.abs));
  const largest = size > 0 ? Math.floor(Math.log10(size)) : 0;
  const stepDigit = Math.floor(Math.log10(step) + 1e-9);
  const clean = (v) => (Math.abs(v) < step * 1e-6 ? 0 : v);  // no "-0.0" nor 1e-17
  if (largest >= 5 || largest <= -4) {
    const digits = Math.max(0, largest - stepDigit);
    return ticks.map((v) => (clean(v) === 0 ? '0' : v.toExponential(digits)));
  }
  const decimals = Math.max(0, -stepDigit);
  return ticks.map((v) => clean(v).toFixed(decimals));
}

// Legend entries of the widths given laid out in rows of `width`: the x and
// row of each, no two overlapping.
export function legendLayout(widths, width, gap = 12) {
  const places = [];
  let x = 0, row = 0;
  for (const w of widths) {
    if (x > 0 && x + w > width) { x = 0; ++row; }
    places.push({ x, row });
    x += w + gap;
  }
  return places;
}

// Series grouped by unit, in order of first appearance: [{ unit, series }].
export function groupByUnit(indices, units) {
  const groups = [];
  for (const i of indices) {
    const unit = units[i] ?? '';
    let group = groups.find((g) => g.unit === unit);
    if (!group) groups.push(group = { unit, series: [] });
    group.series.push(i);
  }
  return groups;
}
