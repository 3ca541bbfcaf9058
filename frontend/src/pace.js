// Pacing of the page's updates: what need not move at the scope's frame rate (the axes
// table, the I/O lamps, the path) is drawn at most every few frames, always with the
// latest values (the last call is never dropped, only delayed).

export function atMostEvery(ms, fn) {
  let last = -Infinity;
  let timer = null;
  let pending = null;
  const run = () => {
    timer = null;
    last = performance.now();
    const args = pending;
    pending = null;
    fn(...args);
  };
  return (...args) => {
    pending = args;
    if (timer != null) return;
    const wait = last + ms - performance.now();
    if (wait <= 0) run();
    else timer = setTimeout(run, wait);
  };
}
