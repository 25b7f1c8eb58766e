// Draws the charts of an aerograsp report with Chart.js (inlined in the page before
// this script). Each <script class="chart-data"> holds one chart's JSON, written by
// app/report/report_charts.cpp, inside the <div class="chart"> that holds its canvas.
// All charts share the page's time axis: drag across a chart to zoom them all to that
// span, Shift+drag to pan, Ctrl+wheel to zoom around the pointer, double-click or
// "Show all" to see the whole record. Hovering shows the values.
// When done, <body data-charts-drawn="N"> counts the charts drawn; a failure sets
// data-charts-error to its message (and is rethrown for the console).
(function () {
  'use strict';
  const charts = [];
  const specOf = new Map();  // canvas -> its chart's JSON
  const drawn = new Set();  // canvases drawn at least once
  const full = { min: Infinity, max: -Infinity };
  let rangeText = null;
  const switchColor = 'rgb(220,40,40)';
  const valueAxisWidthPx = 72;  // the same on every chart, so that their time axes line up

  const rgb = (c) => 'rgb(' + c[0] + ',' + c[1] + ',' + c[2] + ')';
  const fmtTime = (t) => t.toFixed(2);  // the JSON holds times to 10 ms
  const fmtValue = (v) => (v === null || v === undefined ? '-' : Number(v.toPrecision(4)));

  // Grasp switches as vertical lines, and the span being dragged out.
  const overlayPlugin = {
    id: 'aerograspOverlay',
    afterDatasetsDraw(chart) {
      const area = chart.chartArea;
      const x = chart.scales.x;
      const ctx = chart.ctx;
      ctx.save();
      ctx.beginPath();
      ctx.rect(area.left, area.top, area.right - area.left, area.bottom - area.top);
      ctx.clip();
      ctx.strokeStyle = switchColor;
      ctx.fillStyle = switchColor;
      ctx.lineWidth = 1;
      ctx.font = '11px sans-serif';
      for (const m of specOf.get(chart.canvas).markers) {
        const px = x.getPixelForValue(m.t);
        ctx.beginPath();
        ctx.moveTo(px, area.top);
        ctx.lineTo(px, area.bottom);
        ctx.stroke();
        if (m.label) ctx.fillText(m.label, px + 3, area.top + 11);
      }
      const sel = chart.$selection;
      if (sel) {
        ctx.fillStyle = 'rgba(60,120,220,0.18)';
        ctx.fillRect(Math.min(sel.x0, sel.x1), area.top, Math.abs(sel.x1 - sel.x0),
                     area.bottom - area.top);
      }
      ctx.restore();
    },
  };

  // The state's name inside each timeline bar wide enough for it.
  const barLabelPlugin = {
    id: 'aerograspBarLabels',
    afterDatasetsDraw(chart) {
      if (specOf.get(chart.canvas).kind !== 'timeline') return;
      const area = chart.chartArea;
      const ctx = chart.ctx;
      ctx.save();
      ctx.beginPath();
      ctx.rect(area.left, area.top, area.right - area.left, area.bottom - area.top);
      ctx.clip();
      ctx.font = '12px sans-serif';
      ctx.textAlign = 'center';
      ctx.textBaseline = 'middle';
      chart.data.datasets.forEach((dataset, d) => {
        const meta = chart.getDatasetMeta(d);
        if (meta.hidden) return;
        ctx.fillStyle = dataset.$textColor;
        for (const bar of meta.data) {
          const left = Math.max(Math.min(bar.x, bar.base), area.left);
          const right = Math.min(Math.max(bar.x, bar.base), area.right);
          if (ctx.measureText(dataset.label).width + 6 <= right - left)
            ctx.fillText(dataset.label, (left + right) / 2, bar.y);
        }
      });
      ctx.restore();
    },
  };

  // Counts the charts drawn, for the page's readers and tests.
  const drawnPlugin = {
    id: 'aerograspDrawn',
    afterRender(chart) {
      drawn.add(chart.canvas);
      document.body.setAttribute('data-charts-drawn', String(drawn.size));
    },
  };

  function timeScale() {
    return {
      type: 'linear',
      min: full.min,
      max: full.max,
      title: { display: true, text: 'time (s)' },
      ticks: { maxRotation: 0, includeBounds: false },
    };
  }

  function fixWidth(scale) {
    scale.width = valueAxisWidthPx;
  }

  function timeChartConfig(spec) {
    const datasets = spec.lines.map((line) => ({
      label: line.name,
      data: spec.t.map((t, i) => ({ x: t, y: line.v[i] })),
      borderColor: rgb(line.color),
      backgroundColor: rgb(line.color),
      borderWidth: line.width,
      stepped: line.stepped,
      pointRadius: 0,
      pointHoverRadius: 3,
      spanGaps: false,
    }));
    const y = { type: 'linear', title: { display: !!spec.unit, text: spec.unit }, afterFit: fixWidth };
    if (spec.valueNames) {
      y.min = -0.2;
      y.max = spec.valueNames.length - 0.8;
      y.afterBuildTicks = (scale) => {
        scale.ticks = spec.valueNames.map((name, v) => ({ value: v }));
      };
      y.ticks = { autoSkip: false, callback: (v) => spec.valueNames[v] };
    }
    const values = spec.lines.flatMap((line) => line.v.filter((v) => v !== null));
    const cut = spec.yCut !== undefined && values.some((v) => v > spec.yCut);
    if (cut) {
      y.max = spec.yCut;
      y.min = Math.min(0, ...values);
    }
    const unit = spec.unit ? ' ' + spec.unit : '';
    return {
      type: 'line',
      data: { datasets },
      options: {
        parsing: false,
        normalized: true,
        animation: false,
        responsive: true,
        maintainAspectRatio: false,
        interaction: { mode: 'index', intersect: false, axis: 'x' },
        scales: { x: timeScale(), y },
        plugins: {
          title: { display: true, text: spec.title + (cut ? ' (axis cut at ' + spec.yCut + unit + ')' : ''),
                   align: 'start' },
          legend: { display: spec.lines.length > 1, align: 'end' },
          tooltip: {
            callbacks: {
              title: (items) => (items.length ? 't = ' + fmtTime(items[0].parsed.x) + ' s' : ''),
              label: (item) => {
                const v = item.parsed.y;
                if (spec.valueNames && spec.valueNames[v] !== undefined)
                  return item.dataset.label + ': ' + spec.valueNames[v];
                return item.dataset.label + ': ' + fmtValue(v) + unit;
              },
            },
          },
        },
      },
    };
  }

  function timelineConfig(spec) {
    const datasets = spec.states.map((state, s) => ({
      label: state.name,
      data: spec.bars.filter((b) => b[1] === s)
              .map((b) => ({ x: [b[2], b[3]], y: spec.rows[b[0]], note: b[4] })),
      backgroundColor: rgb(state.color),
      borderColor: 'rgb(255,255,255)',
      borderWidth: { left: 1, right: 0, top: 0, bottom: 0 },
      borderSkipped: false,
      grouped: false,
      barPercentage: 0.85,
      categoryPercentage: 1.0,
      $textColor: rgb(state.text),
    }));
    return {
      type: 'bar',
      data: { labels: spec.rows, datasets },
      options: {
        indexAxis: 'y',
        animation: false,
        responsive: true,
        maintainAspectRatio: false,
        interaction: { mode: 'nearest', intersect: true, axis: 'xy' },
        scales: { x: timeScale(), y: { type: 'category', offset: true, grid: { display: false },
                                               afterFit: fixWidth } },
        plugins: {
          title: { display: true, text: spec.title, align: 'start' },
          legend: { display: true, align: 'start', position: 'bottom' },
          tooltip: {
            callbacks: {
              title: (items) => (items.length ? items[0].raw.y : ''),
              label: (item) => {
                const [t0, t1] = item.raw.x;
                return item.dataset.label + ': ' + fmtTime(t0) + ' to ' + fmtTime(t1) + ' s (' +
                       (t1 - t0).toFixed(2) + ' s)';
              },
              afterLabel: (item) => item.raw.note || '',
            },
          },
        },
      },
    };
  }

  function setRange(min, max) {
    const width = Math.min(Math.max(max - min, 1e-3), full.max - full.min);
    min = Math.max(full.min, Math.min(min, full.max - width));
    max = min + width;
    for (const chart of charts) {
      chart.options.scales.x.min = min;
      chart.options.scales.x.max = max;
      chart.update('none');
    }
    const whole = min <= full.min && max >= full.max;
    rangeText.textContent = whole
      ? 'Showing the whole record, ' + fmtTime(full.min) + ' to ' + fmtTime(full.max) + ' s.'
      : 'Showing ' + fmtTime(min) + ' to ' + fmtTime(max) + ' s of ' + fmtTime(full.min) +
          ' to ' + fmtTime(full.max) + ' s.';
  }

  function attachZoom(chart) {
    const canvas = chart.canvas;
    let drag = null;
    const pointerX = (event) => event.clientX - canvas.getBoundingClientRect().left;
    const inArea = (px) => Math.min(Math.max(px, chart.chartArea.left), chart.chartArea.right);
    canvas.addEventListener('mousedown', (event) => {
      const px = pointerX(event);
      if (event.button !== 0 || px < chart.chartArea.left || px > chart.chartArea.right) return;
      const scale = chart.scales.x;
      drag = { x0: px, pan: event.shiftKey, min: scale.min, max: scale.max };
      event.preventDefault();
    });
    window.addEventListener('mousemove', (event) => {
      if (!drag) return;
      const px = inArea(pointerX(event));
      if (drag.pan) {
        const area = chart.chartArea;
        const dt = ((px - drag.x0) / (area.right - area.left)) * (drag.max - drag.min);
        setRange(drag.min - dt, drag.max - dt);
      } else {
        chart.$selection = { x0: drag.x0, x1: px };
        chart.draw();
      }
    });
    window.addEventListener('mouseup', (event) => {
      if (!drag) return;
      const done = drag;
      drag = null;
      if (done.pan) return;
      chart.$selection = null;
      const px = inArea(pointerX(event));
      if (Math.abs(px - done.x0) < 4) {
        chart.draw();
        return;
      }
      const scale = chart.scales.x;
      setRange(scale.getValueForPixel(Math.min(px, done.x0)),
               scale.getValueForPixel(Math.max(px, done.x0)));
    });
    canvas.addEventListener('dblclick', () => setRange(full.min, full.max));
    canvas.addEventListener('wheel', (event) => {
      if (!event.ctrlKey) return;
      event.preventDefault();
      const scale = chart.scales.x;
      const t = scale.getValueForPixel(inArea(pointerX(event)));
      const f = event.deltaY > 0 ? 1.25 : 0.8;
      setRange(t - (t - scale.min) * f, t + (scale.max - t) * f);
    }, { passive: false });
  }

  function addToolbar(before) {
    const bar = document.createElement('div');
    bar.className = 'zoombar';
    const help = document.createElement('span');
    help.textContent = 'Charts: drag across one to zoom all to that time span, Shift+drag to ' +
                       'pan, Ctrl+wheel to zoom, double-click to see all; hover for values, ' +
                       'click a legend entry to hide its line. ';
    rangeText = document.createElement('span');
    const reset = document.createElement('button');
    reset.type = 'button';
    reset.textContent = 'Show all';
    reset.addEventListener('click', () => setRange(full.min, full.max));
    bar.append(help, rangeText, ' ', reset);
    before.parentNode.insertBefore(bar, before);
  }

  function main() {
    const blocks = Array.from(document.querySelectorAll('script.chart-data'));
    if (!blocks.length) return;
    const specs = blocks.map((block) => JSON.parse(block.textContent));
    for (const spec of specs) {
      const times = spec.kind === 'timeline' ? [spec.t0, spec.t1] : spec.t;
      for (const t of times) {
        if (t === null) continue;
        full.min = Math.min(full.min, t);
        full.max = Math.max(full.max, t);
      }
    }
    if (!(full.max > full.min)) {
      full.min = Number.isFinite(full.min) ? full.min : 0;
      full.max = full.min + 1;
    }
    addToolbar(blocks[0].closest('figure') || blocks[0].parentNode);
    Chart.register(overlayPlugin, barLabelPlugin, drawnPlugin);
    blocks.forEach((block, k) => {
      const spec = specs[k];
      const canvas = block.parentNode.querySelector('canvas');
      specOf.set(canvas, spec);
      const config = spec.kind === 'timeline' ? timelineConfig(spec) : timeChartConfig(spec);
      const chart = new Chart(canvas, config);
      charts.push(chart);
      attachZoom(chart);
    });
    setRange(full.min, full.max);
  }

  try {
    main();
  } catch (error) {
    document.body.setAttribute('data-charts-error', String(error && error.message || error));
    throw error;
  }
})();
