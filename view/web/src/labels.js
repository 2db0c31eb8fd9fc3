// Where each robot's label goes so that no two labels overlap, nor a label and another robot:
// the first free one of eight places around the robot (right-above first), then the same places
// a step further out, up to kSteps; where none is free, the place that overlaps least.
const kGapPx = 7;       // From the robot's centre to the label's nearest corner (radius 5 + 2).
const kRobotPx = 6;     // Half the box a robot's circle takes (radius 5, stroke 1).
const kSteps = 4;       // How far out a crowded label may go, in label heights.
// Directions: right-above, right-below, left-above, left-below, right, left, above, below.
const kPlaces = [[1, -1], [1, 1], [-1, -1], [-1, 1], [1, 0], [-1, 0], [0, -1], [0, 1]];

function overlapArea(a, b) {
  const w = Math.min(a.x + a.width, b.x + b.width) - Math.max(a.x, b.x);
  const h = Math.min(a.y + a.height, b.y + b.height) - Math.max(a.y, b.y);
  return w > 0 && h > 0 ? w * h : 0;
}

// The box of a label of `size` ({width, height}) placed in direction [dx, dy] from `anchor`
// ({x, y}, px), `step` label heights further out than the nearest place.
function boxAt(anchor, size, [dx, dy], step) {
  const out = kGapPx + step * size.height;
  const x = dx > 0 ? anchor.x + out : dx < 0 ? anchor.x - out - size.width : anchor.x - size.width / 2;
  const y = dy > 0 ? anchor.y + out : dy < 0 ? anchor.y - out - size.height : anchor.y - size.height / 2;
  return { x, y, width: size.width, height: size.height };
}

// `anchors[i]`: robot i's centre {x, y} in px; `sizes[i]`: its label's {width, height}.
// Returns each label's box {x, y, width, height} (top-left corner), placed in index order.
export function placeLabels(anchors, sizes) {
  const robots = anchors.map((a) => ({ x: a.x - kRobotPx, y: a.y - kRobotPx, width: 2 * kRobotPx, height: 2 * kRobotPx }));
  const placed = [];
  anchors.forEach((anchor, i) => {
    let best = null;
    let bestOverlap = Infinity;
    for (let step = 0; step <= kSteps && bestOverlap > 0; ++step) {
      for (const place of kPlaces) {
        const box = boxAt(anchor, sizes[i], place, step);
        let overlap = 0;
        for (const other of placed) overlap += overlapArea(box, other);
        robots.forEach((robot, j) => { if (j !== i) overlap += overlapArea(box, robot); });
        if (overlap < bestOverlap) [best, bestOverlap] = [box, overlap];
        if (overlap === 0) break;
      }
    }
    placed.push(best);
  });
  return placed;
}
