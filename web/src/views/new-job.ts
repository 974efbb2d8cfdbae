// #/new: a job from one of the example scenes. The charges (mass, position, explosive, burst)
// are form fields; the rest of the scene is JSON to edit. A 422's errors are shown next to the
// field their JSON pointer names; those that name no field are listed under the form.
import { type Charge, client, describe, type Explosive, type JobRequest, ProblemError, type Scene } from "../api";
import { h, mount } from "../dom";
import { fieldFor } from "../pointer";
import { templates } from "../scenes";
import type { View } from "../view";

const CUSTOM = "__custom__";

/** A number from a text field; text that is not one goes to the server as is, to be reported. */
const numberOrText = (text: string): number | string => {
  const trimmed = text.trim();
  return trimmed !== "" && Number.isFinite(Number(trimmed)) ? Number(trimmed) : trimmed;
};

export const newJobView: View = async (root, route, signal) => {
  let explosives: Explosive[] = [];
  try {
    const answer = await client.explosives({ signal });
    if (answer.modified) explosives = answer.value.explosives;
  } catch {
    // the list is a convenience: without it the explosive is typed in
  }
  if (signal.aborted) return;

  const initial = route.query.get("template") ?? (templates.some((t) => t.name === "three_blocks") ? "three_blocks" : templates[0]?.name ?? "");
  const templateSelect = h("select", { id: "template", name: "template", onchange: () => loadTemplate(templateSelect.value) },
    templates.map((t) => h("option", { value: t.name, selected: t.name === initial }, t.name)));
  const chargesBox = h("div", { id: "charges" });
  const jobName = h("input", { id: "job-name", name: "name", type: "text", maxlength: 200, size: 24,
                               placeholder: "Facade, shot 12" });
  const jobLabels = h("input", { id: "job-labels", name: "labels", type: "text", size: 24,
                                 placeholder: "shot=sq010, artist=kim" });
  const priority = h("input", { id: "priority", name: "priority", type: "number", step: 1, min: -100, max: 100, value: "0" });
  const rest = h("textarea", { id: "scene-rest", rows: 16, spellcheck: false, "aria-label": "Rest of the scene (JSON)" });
  const otherErrors = h("div", { id: "other-errors" });
  const message = h("p", { id: "submit-message", role: "status" });
  const submit = h("button", { type: "submit", class: "primary", id: "submit-job" }, "Submit job");
  let charges: Charge[] = [];

  /** A select of the server's explosives plus "custom TNT factor"; a text field without the list. */
  function explosiveField(charge: Charge, index: number): HTMLElement {
    const pointer = `/scene/charges/${index}/explosive`;
    const custom = typeof charge.explosive === "object";
    const name = typeof charge.explosive === "string" ? charge.explosive : "TNT";
    const factor = h("input", { name: `charge-${index}-tnt-factor`, "data-role": "tnt-factor", size: 6,
                                inputmode: "decimal", "aria-label": "TNT factor", hidden: !custom,
                                value: custom ? String((charge.explosive as { tnt_factor: number }).tnt_factor) : "1" });
    if (explosives.length === 0) {
      return h("label", { class: "field", "data-pointer": pointer }, "Explosive ",
        h("input", { name: `charge-${index}-explosive`, "data-role": "explosive", size: 14, value: name }));
    }
    const known = explosives.some((e) => e.name === name);
    const select = h("select", { name: `charge-${index}-explosive`, "data-role": "explosive",
                                 onchange: () => { factor.hidden = select.value !== CUSTOM; } },
      explosives.map((e) => h("option", { value: e.name, selected: !custom && e.name === name }, `${e.name} (×${e.tnt_factor})`)),
      !known && !custom ? h("option", { value: name, selected: true }, name) : null,
      h("option", { value: CUSTOM, selected: custom }, "custom TNT factor…"));
    return h("label", { class: "field", "data-pointer": pointer }, "Explosive ", select,
      h("span", { "data-pointer": `${pointer}/tnt_factor` }, factor));
  }

  function chargeFieldset(charge: Charge, index: number): HTMLElement {
    const base = `/scene/charges/${index}`;
    const position = charge.position ?? [0, 0, 0];
    return h("fieldset", { class: "charge", "data-pointer": base, "data-index": index },
      h("legend", null, `Charge ${index + 1}`),
      h("label", { class: "field", "data-pointer": `${base}/mass` }, "Mass (kg) ",
        h("input", { name: `charge-${index}-mass`, "data-role": "mass", inputmode: "decimal", size: 8, value: String(charge.mass) })),
      h("div", { class: "field", "data-pointer": `${base}/position` }, "Position (m) ",
        ["x", "y", "z"].map((axis, k) =>
          h("label", { class: "axis", "data-pointer": `${base}/position/${k}` }, axis,
            h("input", { name: `charge-${index}-position-${axis}`, "data-role": `position-${k}`, inputmode: "decimal",
                         size: 6, value: String(position[k] ?? 0) })))),
      explosiveField(charge, index),
      h("label", { class: "field", "data-pointer": `${base}/burst` }, "Burst ",
        h("select", { name: `charge-${index}-burst`, "data-role": "burst" },
          ["air", "surface"].map((b) => h("option", { value: b, selected: (charge.burst ?? "air") === b }, b)))),
      h("button", { type: "button", class: "small", disabled: charges.length <= 1,
                    onclick: () => { charges = readCharges(); charges.splice(index, 1); renderCharges(); } }, "Remove"));
  }

  function renderCharges(): void {
    mount(chargesBox, charges.map(chargeFieldset),
      h("button", { type: "button", class: "small", id: "add-charge", onclick: () => {
        charges = readCharges();
        charges.push({ position: [0, 0.5, 0], mass: 1, explosive: "TNT", burst: "air" });
        renderCharges();
      } }, "+ Add charge"));
  }

  /** The charges as the fields say, keeping any field of the template the form does not show. */
  function readCharges(): Charge[] {
    return [...chargesBox.querySelectorAll<HTMLElement>("fieldset.charge")].map((set, index) => {
      const value = (role: string) => set.querySelector<HTMLInputElement | HTMLSelectElement>(`[data-role="${role}"]`)?.value ?? "";
      const select = value("explosive");
      const explosive = select === CUSTOM ? { tnt_factor: numberOrText(value("tnt-factor")) as number } : select.trim();
      return {
        ...charges[index],
        mass: numberOrText(value("mass")) as number,
        position: [0, 1, 2].map((k) => numberOrText(value(`position-${k}`))) as [number, number, number],
        explosive,
        burst: value("burst") as Charge["burst"],
      } as Charge;
    });
  }

  function loadTemplate(name: string): void {
    const template = templates.find((t) => t.name === name);
    if (!template) return;
    const { charges: templateCharges, ...others } = structuredClone(template.scene);
    charges = templateCharges;
    rest.value = JSON.stringify(others, null, 2);
    renderCharges();
    clearErrors();
  }

  function clearErrors(): void {
    root.querySelectorAll(".field-error").forEach((e) => e.remove());
    root.querySelectorAll(".has-error").forEach((e) => e.classList.remove("has-error"));
    otherErrors.replaceChildren();
    message.textContent = "";
    message.className = "";
  }

  function showErrors(problem: ProblemError): void {
    const fields = [...root.querySelectorAll<HTMLElement>("[data-pointer]")];
    const unmatched: { pointer: string; detail: string }[] = [];
    for (const error of problem.pointerErrors) {
      const field = fieldFor(error.pointer, fields);
      if (!field) {
        unmatched.push(error);
        continue;
      }
      field.classList.add("has-error");
      // A position component's message goes under the whole x/y/z group, which has the room.
      const host = field.classList.contains("axis") ? field.parentElement ?? field : field;
      host.append(h("span", { class: "field-error", role: "alert", "data-error-pointer": error.pointer },
        error.pointer === field.dataset.pointer ? error.detail : `${error.pointer}: ${error.detail}`));
    }
    if (unmatched.length) {
      mount(otherErrors, h("div", { class: "error-box" }, h("strong", null, "Other problems in the job"),
        h("ul", { id: "unmatched-errors" }, unmatched.map((e) =>
          h("li", { "data-error-pointer": e.pointer }, h("code", null, e.pointer || "(the whole body)"), " ", e.detail)))));
    }
    message.className = "error";
    message.textContent = `${problem.title}: ${problem.detail}`;
  }

  async function onSubmit(event: Event): Promise<void> {
    event.preventDefault();
    clearErrors();
    let others: Omit<Scene, "charges">;
    try {
      others = JSON.parse(rest.value) as Omit<Scene, "charges">;
    } catch (error) {
      rest.parentElement?.classList.add("has-error");
      rest.after(h("span", { class: "field-error", role: "alert" }, `Not JSON: ${(error as Error).message}`));
      return;
    }
    charges = readCharges();
    // "k=v, k2=v2" → {k: v, k2: v2}; an entry without "=" is sent as a key with an empty value,
    // so the server's message about it points at it.
    const labels = Object.fromEntries(jobLabels.value.split(",").map((item) => item.trim()).filter(Boolean)
      .map((item) => { const at = item.indexOf("="); return at < 0 ? [item, ""] : [item.slice(0, at).trim(), item.slice(at + 1).trim()]; }));
    const request = {
      scene: { ...others, charges } as Scene, priority: numberOrText(priority.value) as number,
      ...(jobName.value.trim() ? { name: jobName.value.trim() } : {}),
      ...(Object.keys(labels).length ? { labels } : {}),
    } satisfies JobRequest;
    submit.disabled = true;
    message.textContent = "Submitting…";
    try {
      const job = await client.submitJob(request);
      location.hash = `#/jobs/${job.id}`;
    } catch (error) {
      if (error instanceof ProblemError && error.pointerErrors.length) showErrors(error);
      else {
        message.className = "error";
        message.textContent = describe(error);
      }
    } finally {
      submit.disabled = false;
    }
  }

  mount(root, h("h1", null, "New job"),
    h("form", { id: "new-job", class: "new-job", onsubmit: (e: Event) => void onSubmit(e), novalidate: true },
      h("div", { class: "toolbar" }, h("label", null, "Template ", templateSelect),
        h("label", { class: "field", "data-pointer": "/priority" }, "Priority ", priority),
        h("label", { class: "field", "data-pointer": "/name" }, "Name ", jobName),
        h("label", { class: "field", "data-pointer": "/labels" }, "Labels ", jobLabels)),
      h("h2", null, "Charges"), chargesBox,
      h("h2", null, "Rest of the scene"),
      h("p", { class: "muted small" }, "Objects, generators, environment and simulation, as in docs/scene-format.md."),
      h("div", { class: "field" }, rest),
      otherErrors,
      h("div", { class: "toolbar" }, submit, message)));
  loadTemplate(initial);
};
