// The plot's axis numbers (viewer/src/axis.js), by node's test runner:
//   node --test tests/viewer/axis_test.mjs
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { niceAxis, tickLabels, legendLayout, groupByUnit, roundUp } from '../../viewer/src/axis.js';

// Whether x is 1, 2 or 5 times a power of ten.
function isRound(x) {
  const mantissa = x / 10 ** Math.floor(Math.log10(x) + 1e-12);
  return [1, 2, 5, 10].some((m) => Math.abs(mantissa - m) < 1e-9);
}

test('ticks are round, evenly spaced and cover the values', () => {
  for (const [lo, hi] of [[0, 1], [-0.37, 2.9], [12.5, 25.3], [-3e-7, 8e-7], [1e5, 3.3e6], [-25, -24.1]]) {
    const a = niceAxis(lo, hi, 5);
    assert.ok(isRound(a.step), `step ${a.step} of [${lo}, ${hi}]`);
    assert.ok(a.lo <= lo && a.hi >= hi, `[${a.lo}, ${a.hi}] covers [${lo}, ${hi}]`);
    assert.ok(a.ticks.length >= 3 && a.ticks.length <= 12, `${a.ticks.length} ticks for [${lo}, ${hi}]`);
    a.ticks.slice(1).forEach((v, k) => assert.ok(Math.abs(v - a.ticks[k] - a.step) < 1e-9 * a.step));
    assert.ok(a.hi - a.lo < (hi - lo) + 2 * a.step + 1e-12, 'no more than a step of margin either side');
  }
});

test('a constant or round-off-flat series gets a readable axis', () => {
  // An energy of 12.3 J drifting by 2e-14 J: drawn flat, labels of a few digits.
  const a = niceAxis(12.3, 12.3 + 2.2e-14);
  const labels = tickLabels(a.ticks, a.step);
  assert.ok(labels.every((l) => l.length <= 12), labels.join(' '));
  assert.equal(new Set(labels).size, labels.length, 'distinct labels');
  const zero = niceAxis(0, 0);
  assert.ok(zero.lo < 0 && zero.hi > 0);
  const swapped = niceAxis(3, 1);
  assert.ok(swapped.lo <= 1 && swapped.hi >= 3);
});

test('labels carry the digits the step needs and no "-0"', () => {
  assert.deepEqual(tickLabels([-0.5, 0, 0.5, 1], 0.5), ['-0.5', '0.0', '0.5', '1.0']);
  assert.deepEqual(tickLabels([0, 20, 40], 20), ['0', '20', '40']);
  assert.deepEqual(tickLabels([-0.2, -1e-17, 0.2], 0.2), ['-0.2', '0.0', '0.2']);
  // Small and large values in exponents, each label telling its tick apart.
  assert.deepEqual(tickLabels([0, 5e-15, 1e-14, 1.5e-14], 5e-15), ['0', '5.0e-15', '1.0e-14', '1.5e-14']);
  assert.deepEqual(tickLabels([2e6, 4e6], 2e6), ['2e+6', '4e+6']);
  const a = niceAxis(-3e-7, 8e-7);
  const labels = tickLabels(a.ticks, a.step);
  assert.equal(new Set(labels).size, labels.length);
  labels.forEach((l, k) => assert.ok(Math.abs(Number(l) - a.ticks[k]) <= a.step * 1e-6, `${l} reads as ${a.ticks[k]}`));
});

test('legend entries never overlap and stay inside the width', () => {
  const widths = [60, 140, 35, 200, 90, 90, 90, 45, 300];
  const width = 320, gap = 12;
  const places = legendLayout(widths, width, gap);
  places.forEach((p, k) => {
    assert.ok(p.x + widths[k] <= width || p.x === 0, `entry ${k} inside the row`);
    places.slice(0, k).forEach((q, j) => {
      if (q.row === p.row) assert.ok(q.x + widths[j] + gap <= p.x || p.x + widths[k] + gap <= q.x, `entries ${j} and ${k}`);
    });
  });
  assert.ok(places[places.length - 1].row >= 3, 'long legends wrap onto rows');
});

test('series are grouped by unit in order of appearance', () => {
  const units = ['s', 'm', 'm', 'rad', 'm', 'rad', ''];
  assert.deepEqual(groupByUnit([1, 3, 2, 5, 6], units),
    [{ unit: 'm', series: [1, 2] }, { unit: 'rad', series: [3, 5] }, { unit: '', series: [6] }]);
});

test('round numbers: 1, 2 or 5 times a power of ten, not below the value', () => {
  assert.deepEqual([0.63, 1, 1.2, 3, 7, 0.0021, 4e5].map(roundUp), [1, 1, 2, 5, 10, 0.005, 5e5]);
});
