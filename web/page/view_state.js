// The view a page shows, read from and kept in its URL:
// ?map=NAME&yaw=DEG&pitch=DEG&exposure=EV&background=black|env|alpha&tone=clamp|aces&ui=0
// with relight's defaults (the first map, no rotation, exposure 0, the map
// behind the subject, clamp).
export const kBackgrounds = ["env", "black", "alpha"];
export const kTones = ["clamp", "aces"];

export function readView(search, mapNames) {
  const q = new URLSearchParams(search);
  const problems = [];
  const number = (key) => {
    if (!q.has(key)) return 0;
    const v = Number(q.get(key));
    if (q.get(key).trim() === "" || !Number.isFinite(v)) {
      problems.push(`${key}=${q.get(key)} is not a number`);
      return 0;
    }
    return v;
  };
  const choice = (key, allowed) => {
    if (!q.has(key)) return allowed[0];
    if (allowed.includes(q.get(key))) return q.get(key);
    problems.push(`${key}=${q.get(key)} is not one of ${allowed.join(", ")}`);
    return allowed[0];
  };
  let map = q.get("map") ?? mapNames[0];
  if (!mapNames.includes(map)) {
    problems.push(`map=${map} is not one of ${mapNames.join(", ")}`);
    map = mapNames[0];
  }
  const view = {
    map, yaw: number("yaw"), pitch: number("pitch"), exposure: number("exposure"),
    background: choice("background", kBackgrounds), tone: choice("tone", kTones),
    ui: q.get("ui") !== "0",
  };
  return { view, problems };
}

/** The URL's query for a view: only what differs from the defaults. */
export function viewQuery(view, mapNames) {
  const q = new URLSearchParams();
  if (view.map !== mapNames[0]) q.set("map", view.map);
  for (const key of ["yaw", "pitch", "exposure"])
    if (view[key] !== 0) q.set(key, String(round(view[key])));
  if (view.background !== "env") q.set("background", view.background);
  if (view.tone !== "clamp") q.set("tone", view.tone);
  if (!view.ui) q.set("ui", "0");
  const text = q.toString();
  return text ? `?${text}` : "";
}

/** The CLI's arguments for a view. */
export function cliArguments(view) {
  const parts = [];
  if (view.yaw !== 0 || view.pitch !== 0)
    parts.push(view.pitch !== 0 ? `--rotate ${round(view.yaw)},${round(view.pitch)},0` : `--rotate ${round(view.yaw)}`);
  if (view.exposure !== 0) parts.push(`--exposure ${round(view.exposure)}`);
  if (view.background !== "env") parts.push(`--background ${view.background}`);
  if (view.tone !== "clamp") parts.push(`--tone ${view.tone}`);
  return parts.join(" ");
}

function round(v) {
  return Math.round(v * 1000) / 1000;
}
