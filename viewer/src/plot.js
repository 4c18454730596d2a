// The time histories chosen, against time: one panel per unit (metres apart
// from radians), each with ticks, a grid, its unit as the axis label and a
// legend in rows; a colour per series (dashed once the ten are used), and a
// cursor at the current time.
import { niceAxis, tickLabels, legendLayout, groupByUnit } from './axis.js';

// Tableau's ten: told apart by most eyes, also printed.
export const palette = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#76b7b2',
  '#edc948', '#b07aa1', '#ff9da7', '#9c755f', '#bab0ac'];
const dashes = [[], [7, 4], [2, 3]];
const font = '11px system-ui, sans-serif';

export class Plot {
  constructor(canvas, series) {
    this.canvas = canvas;
    this.names = series.names;
    this.columns = series.columns;
    this.units = series.units && series.units.length === series.names.length
      ? series.units : series.names.map(() => '');
    this.chosen = new Set(this.names.slice(1, 5));
    this.time = 0;
  }

  // The series shown, in the order of the list, each with its line style.
  shown() {
    const indices = this.names.map((n, i) => i).filter((i) => i > 0 && this.chosen.has(this.names[i]));
    return indices.map((i, k) => ({ i, colour: palette[k % palette.length],
      dash: dashes[Math.floor(k / palette.length) % dashes.length] }));
  }

  draw() {
    const c = this.canvas;
    const ratio = window.devicePixelRatio || 1;
    c.width = c.clientWidth * ratio;
    c.height = c.clientHeight * ratio;
    const g = c.getContext('2d');
    g.scale(ratio, ratio);
    const w = c.clientWidth, h = c.clientHeight;
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    const t = this.columns[0];
    if (!t || t.length === 0) return;
    g.font = font;
    const shown = this.shown();
    const style = new Map(shown.map((s) => [s.i, s]));
    const groups = groupByUnit(shown.map((s) => s.i), this.units);
    const time = niceAxis(t[0], t[t.length - 1] > t[0] ? t[t.length - 1] : t[0] + 1, Math.max(2, Math.floor(w / 90)));
    time.lo = t[0];  // the run's own span, ticks inside it
    time.hi = Math.max(t[t.length - 1], t[0] + 1e-12);
    time.ticks = time.ticks.filter((v) => v >= time.lo - 1e-9 * time.step && v <= time.hi + 1e-9 * time.step);
    const bottom = 34, top = 6, panelGap = 10;
    const height = (h - top - bottom - panelGap * Math.max(0, groups.length - 1)) / Math.max(1, groups.length);
    const axes = groups.map((group) => this.valueAxis(group, height));
    const labelWidth = Math.max(0, ...axes.map((a) => Math.max(...a.labels.map((l) => g.measureText(l).width))));
    const left = 22 + labelWidth + 6, right = 12;
    const x = (v) => left + ((v - time.lo) / (time.hi - time.lo)) * (w - left - right);
    groups.forEach((group, p) => {
      const y0 = top + p * (height + panelGap);
      this.drawPanel(g, group, axes[p], style, { x, left, right, w, y0, height, time, last: p === groups.length - 1 });
    });
    if (groups.length === 0) {
      g.fillStyle = '#777';
      g.fillText('Tick a series to plot it.', 12, 20);
    }
  }

  valueAxis(group, height) {
    let lo = Infinity, hi = -Infinity;
    for (const i of group.series) for (const v of this.columns[i]) if (isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (!(hi >= lo)) { lo = 0; hi = 1; }
    const axis = niceAxis(lo, hi, Math.max(2, Math.min(6, Math.floor(height / 40))));
    axis.labels = tickLabels(axis.ticks, axis.step);
    return axis;
  }

  drawPanel(g, group, axis, style, f) {
    const { x, left, right, w, time } = f;
    // The legend first, in rows above the panel's frame.
    const entries = group.series.map((i) => this.names[i]);
    const places = legendLayout(entries.map((n) => 22 + g.measureText(n).width), w - left - right);
    const rows = places.length ? places[places.length - 1].row + 1 : 0;
    const legendHeight = 14 * rows + 4;
    const top = f.y0 + legendHeight, bottom = f.y0 + f.height;
    const y = (v) => top + ((axis.hi - v) / (axis.hi - axis.lo)) * (bottom - top);
    group.series.forEach((i, k) => {
      const s = style.get(i), px = left + places[k].x, py = f.y0 + 10 + 14 * places[k].row;
      g.strokeStyle = s.colour;
      g.setLineDash(s.dash);
      g.lineWidth = 2;
      g.beginPath();
      g.moveTo(px, py - 4);
      g.lineTo(px + 16, py - 4);
      g.stroke();
      g.fillStyle = '#222';
      g.textAlign = 'left';
      g.fillText(entries[k], px + 20, py);
    });
    g.setLineDash([]);
    g.lineWidth = 1;
    // Grid and ticks.
    g.strokeStyle = '#e4e4e8';
    g.fillStyle = '#444';
    g.textAlign = 'right';
    g.textBaseline = 'middle';
    axis.ticks.forEach((v, k) => {
      g.beginPath();
      g.moveTo(left, y(v));
      g.lineTo(w - right, y(v));
      g.stroke();
      g.fillText(axis.labels[k], left - 5, y(v));
    });
    g.textAlign = 'center';
    g.textBaseline = 'top';
    const timeLabels = tickLabels(time.ticks, time.step);
    time.ticks.forEach((v, k) => {
      g.beginPath();
      g.moveTo(x(v), top);
      g.lineTo(x(v), bottom);
      g.stroke();
      if (f.last) g.fillText(timeLabels[k], x(v), bottom + 4);
    });
    g.textBaseline = 'alphabetic';
    if (f.last) g.fillText('t (s)', (left + w - right) / 2, bottom + 30);
    g.strokeStyle = '#999';
    g.strokeRect(left, top, w - left - right, bottom - top);
    // The unit, along the axis.
    if (group.unit) {
      g.save();
      g.translate(12, (top + bottom) / 2);
      g.rotate(-Math.PI / 2);
      g.textAlign = 'center';
      g.fillText(group.unit, 0, 0);
      g.restore();
    }
    // The series, clipped to the frame.
    g.save();
    g.beginPath();
    g.rect(left, top, w - left - right, bottom - top);
    g.clip();
    const t = this.columns[0];
    for (const i of group.series) {
      const s = style.get(i);
      g.strokeStyle = s.colour;
      g.setLineDash(s.dash);
      g.lineWidth = 1.5;
      g.beginPath();
      this.columns[i].forEach((v, j) => (j ? g.lineTo(x(t[j]), y(v)) : g.moveTo(x(t[j]), y(v))));
      g.stroke();
    }
    g.restore();
    g.setLineDash([]);
    g.lineWidth = 1;
    g.strokeStyle = '#000';
    g.beginPath();
    g.moveTo(x(t[0] + this.time), top);
    g.lineTo(x(t[0] + this.time), bottom);
    g.stroke();
  }
}
