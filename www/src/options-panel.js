// The options form, built from HandRig.optionDescriptions() rather than by hand, so options
// the package gains (hand strategies, arm solvers, filters) appear without touching the page.
//
// A description is { path (or name): "alignment.weight", type: "boolean" | "enum" | "number" |
// "numbers" | "points", values?, min?, max?, length?, names?, default, description } ("numbers": a
// fixed-length array, edited as comma-separated text; "points": an object of named [x, y, z],
// edited as JSON text). Dotted paths become nested option objects:
// "alignment.weight" -> { alignment: { weight } }. A number whose default is null (e.g. a preset
// that is automatic unless set) gets an "auto" checkbox; while it is ticked the option is left
// out so the package's own default applies.

/** The dotted path of a description. */
export const pathOf = (d) => d.path ?? d.name;

/** Sets `value` at dotted `path` in `obj`, creating objects on the way. */
export function setPath(obj, path, value) {
  const keys = path.split(".");
  let o = obj;
  for (const k of keys.slice(0, -1)) o = o[k] ??= {};
  o[keys.at(-1)] = value;
  return obj;
}

/** Reads dotted `path` from `obj` (undefined when absent). */
export function getPath(obj, path) {
  return path.split(".").reduce((o, k) => (o == null ? undefined : o[k]), obj);
}

// A range input snaps to min + k * step in doubles (0.05 + 2 * 0.05 is 0.15000000000000002):
// its values are rounded to 6 digits, and kept within the package's range (which it gives as
// the shortest decimals of Rust's f32 values: pi/2 is 1.5707964, which rounds up to 1.5708,
// outside the range).
const clean = (x) => (Number.isFinite(x) ? Number(Number(x).toPrecision(6)) : x);
const within = (x, d) => (Number.isFinite(x) ? Math.min(d.max ?? Infinity, Math.max(d.min ?? -Infinity, clean(x))) : x);

const fmt = (v) => (Number.isInteger(v) ? String(v) : Number(v).toFixed(3).replace(/0+$/, "").replace(/\.$/, ""));

/**
 * Builds the form into `form` and calls `onChange(options, path)` on every edit.
 * Returns { values: () => options, set(path, value), paths }.
 */
export function buildOptionsPanel(form, descriptions, onChange) {
  form.textContent = "";
  const values = new Map();
  const controls = new Map();
  const groups = new Map();

  const groupFor = (path) => {
    const top = path.includes(".") ? path.split(".")[0] : null;
    if (!top) return form;
    if (!groups.has(top)) {
      const fs = document.createElement("fieldset");
      const lg = document.createElement("legend");
      lg.textContent = top;
      fs.append(lg);
      form.append(fs);
      groups.set(top, fs);
    }
    return groups.get(top);
  };

  const emit = (path) => onChange(options(), path);

  for (let d of descriptions) {
    const path = pathOf(d);
    if (!path) continue;
    const wrap = document.createElement("div");
    wrap.className = "opt";
    wrap.dataset.path = path;
    const name = document.createElement("div");
    name.className = "name";
    name.textContent = path.includes(".") ? path.split(".").slice(1).join(".") : path;
    const ctl = document.createElement("div");
    ctl.className = "ctl";
    const desc = document.createElement("div");
    desc.className = "desc";
    desc.textContent = d.description ?? "";
    values.set(path, d.default ?? null);

    if (d.type === "boolean") {
      const cb = document.createElement("input");
      cb.type = "checkbox";
      cb.name = path;
      cb.checked = !!d.default;
      cb.addEventListener("change", () => {
        values.set(path, cb.checked);
        emit(path);
      });
      ctl.append(cb);
      controls.set(path, { set: (v) => (cb.checked = !!v) });
    } else if (d.type === "enum") {
      const sel = document.createElement("select");
      sel.name = path;
      for (const v of d.values ?? []) {
        const o = document.createElement("option");
        o.value = String(v);
        o.textContent = String(v);
        sel.append(o);
      }
      sel.value = String(d.default);
      sel.addEventListener("change", () => {
        values.set(path, sel.value);
        emit(path);
      });
      ctl.append(sel);
      controls.set(path, { set: (v) => (sel.value = String(v)) });
    } else if (d.type === "number") {
      values.set(path, d.default ?? null);
      const ranged = Number.isFinite(d.min) && Number.isFinite(d.max);
      const input = document.createElement("input");
      input.name = path;
      input.type = ranged ? "range" : "number";
      if (ranged) {
        input.min = String(d.min);
        input.max = String(d.max);
        input.step = String(d.step ?? (d.max - d.min) / 100);
      } else {
        input.step = "any";
        if (Number.isFinite(d.min)) input.min = String(d.min);
      }
      const out = document.createElement("output");
      const optional = d.default == null;
      let auto = null;
      const start = optional ? (Number.isFinite(d.min) && d.min > 0 ? d.min : 1) : d.default;
      input.value = String(start);
      out.textContent = optional ? "auto" : fmt(start);
      const commit = () => {
        const v = within(Number(input.value), d);
        if (auto?.checked) {
          values.set(path, null);
          out.textContent = "auto";
        } else if (Number.isFinite(v)) {
          values.set(path, v);
          out.textContent = fmt(v);
        }
        emit(path);
      };
      input.addEventListener(ranged ? "input" : "change", commit);
      if (optional) {
        const lab = document.createElement("label");
        auto = document.createElement("input");
        auto.type = "checkbox";
        auto.checked = true;
        auto.name = `${path}:auto`;
        input.disabled = true;
        auto.addEventListener("change", () => {
          input.disabled = auto.checked;
          commit();
        });
        lab.append(auto, " auto");
        ctl.append(lab);
      }
      ctl.append(input);
      if (ranged || optional) ctl.append(out);
      controls.set(path, {
        set: (v) => {
          if (auto) {
            auto.checked = v == null;
            input.disabled = auto.checked;
          }
          if (v != null) input.value = String(v);
          out.textContent = v == null ? "auto" : fmt(v);
        },
      });
    } else if (d.type === "numbers") {
      // A fixed-length array of numbers (d.length, each in d.min..d.max), typed as "a, b, c".
      const input = document.createElement("input");
      input.type = "text";
      input.name = path;
      input.spellcheck = false;
      input.value = (d.default ?? []).join(", ");
      input.title = `${d.length} numbers, each in ${d.min}..${d.max}, separated by commas`;
      input.addEventListener("change", () => {
        const v = input.value.split(",").map((s) => Number(s.trim()));
        const ok = v.length === d.length && v.every((x) => Number.isFinite(x) && x >= d.min && x <= d.max);
        input.classList.toggle("invalid", !ok);
        if (!ok) return;
        values.set(path, v);
        emit(path);
      });
      ctl.append(input);
      controls.set(path, { set: (v) => (input.value = v == null ? "" : v.join(", ")) });
    } else if (d.type === "points") {
      // An object of named points { name: [x, y, z] } (d.names), typed as JSON; empty = unset.
      const input = document.createElement("input");
      input.type = "text";
      input.name = path;
      input.spellcheck = false;
      input.placeholder = `{"${d.names?.[0] ?? "name"}": [0, 0.05, 0.1]}`;
      input.title = `JSON: an object with any of ${(d.names ?? []).join(", ")}, each [x, y, z] in meters`;
      input.addEventListener("change", () => {
        const text = input.value.trim();
        let v = null;
        if (text !== "") {
          try {
            v = JSON.parse(text);
          } catch {
            input.classList.add("invalid");
            return;
          }
        }
        input.classList.remove("invalid");
        values.set(path, v);
        emit(path);
      });
      ctl.append(input);
      controls.set(path, { set: (v) => (input.value = v == null ? "" : JSON.stringify(v)) });
    } else {
      // A type this page does not know yet: show it read-only rather than guess.
      const code = document.createElement("code");
      code.textContent = JSON.stringify(d.default);
      ctl.append(code);
    }
    wrap.append(name, ctl, desc);
    groupFor(path).append(wrap);
  }

  /** The nested options object; null values (automatic) are left out. */
  function options() {
    const o = {};
    for (const [path, v] of values) if (v != null) setPath(o, path, v);
    return o;
  }

  return {
    paths: [...values.keys()],
    values: options,
    /** Sets an option as if the user had edited it (the form follows); emits onChange. */
    set(path, value) {
      if (!values.has(path)) throw new Error(`unknown option "${path}"`);
      values.set(path, value);
      controls.get(path)?.set(value);
      emit(path);
    },
  };
}
