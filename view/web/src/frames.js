// The frame list of one link: losses.csv.gz's rows for a second, lost ones marked.
import { select } from 'd3-selection';

export class FrameList {
  constructor(table, title, note, columns) {
    this.table = select(table);
    this.title = select(title);
    this.note = select(note);
    this.columns = columns;
    this.table.select('thead').selectAll('tr').data([columns]).join('tr')
      .selectAll('th').data((c) => c).join('th').text((c) => c);
  }

  // Shows `answer` (/api/frames) for the link `from` -> `station`.
  show(answer, robotName) {
    const startS = answer.start_ns / 1e9;
    this.title.text(`Frames ${robotName(answer.from)} -> ${robotName(answer.station)}, ` +
      `[${startS.toFixed(1)} s, ${(answer.end_ns / 1e9).toFixed(1)} s)`);
    const shown = answer.rows.length < answer.total ? ` (first ${answer.rows.length} shown)` : '';
    const cause = this.columns.indexOf('cause');
    const lost = answer.rows.filter((r) => r[cause] !== 'decoded').length;
    this.note.text(`${answer.total} rows, ${lost} not decoded${shown}`);
    this.table
      .attr('data-from', answer.from).attr('data-to', answer.station)
      .attr('data-start-ns', answer.start_ns).attr('data-end-ns', answer.end_ns)
      .attr('data-total', answer.total);
    this.table.select('tbody').selectAll('tr').data(answer.rows).join('tr')
      .classed('lost', (r) => r[cause] !== 'decoded')
      .selectAll('td').data((r) => r).join('td').text((c) => c);
  }

  clear() {
    this.table.select('tbody').selectAll('tr').remove();
    this.table.attr('data-from', null).attr('data-to', null);
    this.title.text('Frames');
    this.note.text('Click a link to list its frames.');
  }
}
