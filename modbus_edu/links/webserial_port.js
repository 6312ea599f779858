// The page's side of mb.browser_serial(): owns the Web Serial port, moves bytes, holds no protocol.
// Kernel -> page: {type: "write", hex}, {type: "close"}.
// Page -> kernel: {type: "ready" | "unavailable" | "opened" | "data" | "lost" | "closed" | "error", ...}.

const toHex = (bytes) => Array.from(bytes, (b) => b.toString(16).padStart(2, "0")).join("");
const fromHex = (hex) => new Uint8Array((hex.match(/../g) || []).map((h) => parseInt(h, 16)));
// errors after which the port reads on (a new readable stream follows); anything else: the port is lost
const LINE_ERRORS = ["BreakError", "FramingError", "ParityError", "BufferOverrunError"];

function setStatus(model, text) {
  model.set("status", text);
  model.save_changes();
}

async function readLoop(model, state) {
  while (state.port && state.port.readable && !state.closing) {
    const reader = state.port.readable.getReader();
    state.reader = reader;
    try {
      for (;;) {
        const { value, done } = await reader.read();
        if (done) break;
        if (value && value.length) model.send({ type: "data", hex: toHex(value), t: performance.now() });
      }
    } catch (err) {
      if (!LINE_ERRORS.includes(err && err.name)) {
        lost(model, state, String(err && err.message ? err.message : err));
        return;
      }
      model.send({ type: "line-error", reason: String(err.name) });
    } finally {
      try { reader.releaseLock(); } catch (e) { /* already released */ }
      state.reader = null;
    }
  }
  if (!state.closing && state.port) lost(model, state, "the port stopped delivering bytes");
}

function lost(model, state, reason) {
  if (!state.port) return;
  state.port = null;
  model.send({ type: "lost", reason });
  setStatus(model, `port lost: ${reason}`);
}

async function choose(model, state) {
  try {
    const port = await navigator.serial.requestPort();
    if (state.port) await close(model, state, true);
    await port.open({
      baudRate: model.get("baudrate"), dataBits: model.get("databits"),
      stopBits: model.get("stopbits"), parity: model.get("parity"),
    });
    state.port = port;
    state.closing = false;
    const info = port.getInfo ? port.getInfo() : {};
    const settings = `${model.get("baudrate")} baud, ${model.get("databits")} data bits, ` +
      `parity ${model.get("parity")}, ${model.get("stopbits")} stop bit(s)`;
    model.send({ type: "opened", info });
    setStatus(model, `port open: ${settings}`);
    readLoop(model, state);
  } catch (err) {
    const reason = String(err && err.message ? err.message : err);
    model.send({ type: "error", reason });
    setStatus(model, `no port: ${reason}`);
  }
}

async function close(model, state, quiet) {
  const port = state.port;
  state.closing = true;
  if (!port) return;
  try { if (state.reader) await state.reader.cancel(); } catch (e) { /* gone already */ }
  try { await state.writing; await port.close(); } catch (e) { /* gone already */ }
  state.port = null;
  if (!quiet) {
    model.send({ type: "closed" });
    setStatus(model, "port closed");
  }
}

function initialize({ model }) {
  // the port's state lives here, once per model; a view's button asks for a port by counting a click
  // (render may get another wrapper of the same model, so nothing is hung on the model object itself)
  const state = { port: null, reader: null, closing: false, writing: Promise.resolve() };
  model.on("change:choose_clicks", () => choose(model, state));
  const available = typeof navigator !== "undefined" && "serial" in navigator;
  model.send(available ? { type: "ready" } : { type: "unavailable", reason: "no navigator.serial" });
  if (available && navigator.serial.addEventListener) {
    navigator.serial.addEventListener("disconnect", (event) => {
      if (state.port && event.target === state.port) lost(model, state, "the adapter was unplugged");
    });
  }
  model.on("msg:custom", (msg) => {
    if (msg.type === "write") {
      const port = state.port;
      if (!port || !port.writable) {
        model.send({ type: "lost", reason: "no open port to write to" });
        return;
      }
      const bytes = fromHex(msg.hex);
      state.writing = state.writing.then(async () => {
        const writer = port.writable.getWriter();
        try { await writer.write(bytes); } finally { writer.releaseLock(); }
      }).catch((err) => lost(model, state, String(err && err.message ? err.message : err)));
    } else if (msg.type === "close") {
      close(model, state, false);
    }
  });
}

function render({ model, el }) {
  const box = document.createElement("div");
  box.className = "mbe-webserial";
  if (!(typeof navigator !== "undefined" && "serial" in navigator)) {
    const line = document.createElement("p");
    line.className = "mbe-webserial-unavailable";
    line.setAttribute("role", "status");
    line.textContent = model.get("no_web_serial");
    box.appendChild(line);
    el.appendChild(box);
    return;
  }
  const button = document.createElement("button");
  button.className = "mbe-webserial-choose jupyter-button";
  button.type = "button";
  button.textContent = "choose serial port";
  button.title = "ask the browser for the serial port of your USB adapter";
  button.addEventListener("click", () => {
    model.set("choose_clicks", model.get("choose_clicks") + 1);  // initialize's listener asks for the port
    model.save_changes();
  });
  const status = document.createElement("span");
  status.className = "mbe-webserial-status";
  status.setAttribute("role", "status");
  status.style.marginLeft = "0.6em";
  const show = () => { status.textContent = model.get("status") || "no port chosen yet"; };
  show();
  model.on("change:status", show);
  box.append(button, status);
  el.appendChild(box);
  return () => model.off("change:status", show);
}

export default { initialize, render };
