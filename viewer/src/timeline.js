// Frame lookup shared by file and live playback: the recording's frame
// times are sorted, so the frame shown at time t is the last one at or
// before t (binary search).

/** Index of the last frame whose time is <= t (0 if t precedes all). */
export function frameIndexAt(times, t) {
  let lo = 0;
  let hi = times.length - 1;
  if (hi < 0 || t <= times[0]) return 0;
  if (t >= times[hi]) return hi;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (times[mid] <= t) lo = mid;
    else hi = mid;
  }
  return lo;
}

/** Formats seconds for the clock display. */
export function formatTime(t) {
  return `${t.toFixed(3)} s`;
}
