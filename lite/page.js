// The course's page script, added by lite/build_site.py to the site's lab/ and notebooks/ pages.
//
// 1. A stop the learner can see.  When a cell stops with an error, the cell and its message are scrolled
//    into view (Run All leaves the page at the last cell, far below the one that stopped).
//    And the toolbar's busy indicator follows the kernel: JupyterLite's kernel client answers an error by
//    cancelling the requests queued behind it (to stop Run All, as JupyterLab does) but sends nothing for
//    them, where a Jupyter kernel sends each an aborted execute_reply and an idle status.  JupyterLab's
//    execution indicator counts a request as done only when an idle status names it, so it stayed "busy"
//    while the status bar said Idle.  Here each cancelled request gets the idle status the kernel owed
//    it, on the kernel connection's message signal that the indicator reads.
// 2. A kernel that cannot start says so.  The published site loads Python (Pyodide) from its CDN; where a
//    firewall blocks it, the page would say "Python (Pyodide) | Unknown" for minutes.  Here the CDN is
//    probed when the page opens, and if it cannot be reached (or the kernel has not started within
//    START_BOUND_S) a banner says what failed and points to the offline site and to Binder.
(function () {
  "use strict";
  const SETTINGS = __SETTINGS__; // {cdn: URL or "", binder: URL, probe_timeout_s, start_bound_s}
  const watched = new WeakSet();

  function banner(text, link) {
    if (document.getElementById("mbe-page-alert")) return;
    const box = document.createElement("div");
    box.id = "mbe-page-alert";
    box.setAttribute("role", "alert");
    box.style.cssText = "position:fixed;top:0;left:0;right:0;z-index:10000;padding:12px 16px;" +
      "background:#fff3bf;color:#5c3c00;border-bottom:2px solid #e8590c;font:15px/1.4 sans-serif";
    box.textContent = text + " ";
    const a = document.createElement("a");
    a.href = link;
    a.textContent = "Open the course on Binder";
    box.appendChild(a);
    const close = document.createElement("button");
    close.textContent = "\u00d7";
    close.setAttribute("aria-label", "Close this message");
    close.style.cssText = "margin-left:12px;border:0;background:none;font-size:18px;cursor:pointer";
    close.onclick = () => box.remove();
    box.appendChild(close);
    document.body.appendChild(box);
  }

  async function probeCdn() {
    if (!SETTINGS.cdn) return;
    const host = new URL(SETTINGS.cdn).host;
    const abort = new AbortController();
    const timer = setTimeout(() => abort.abort(), SETTINGS.probe_timeout_s * 1000);
    try {
      await fetch(SETTINGS.cdn, { method: "HEAD", mode: "no-cors", cache: "no-store", signal: abort.signal });
    } catch (error) {
      banner(`Python cannot start: this page loads Python (Pyodide) from ${host}, which this network ` +
             `does not reach (${abort.signal.aborted ? "no answer within " + SETTINGS.probe_timeout_s +
             " s" : "the request was refused or blocked"}; a school firewall?). Use the offline copy of ` +
             "the course (make lite OFFLINE=1: a USB stick or the school's own web server), or Binder.",
             SETTINGS.binder);
    } finally {
      clearTimeout(timer);
    }
  }

  function kernelStarted() {
    const app = window.jupyterapp;
    if (!app) return false;
    for (const widget of app.shell.widgets("main")) {
      const context = widget.sessionContext;
      if (context && context.session && context.session.kernel &&
          ["idle", "busy"].includes(context.session.kernel.status)) return true;
    }
    return false;
  }

  function watchStart() {
    setTimeout(() => {
      const notebookOpen = window.jupyterapp &&
        [...window.jupyterapp.shell.widgets("main")].some((w) => w.sessionContext);
      if (notebookOpen && !kernelStarted()) {
        banner(`Python has not started within ${SETTINGS.start_bound_s} s` +
               (SETTINGS.cdn ? ` (it loads from ${new URL(SETTINGS.cdn).host}, which may be blocked here)` : "") +
               ". Reload the page; if it stays so, use the offline copy of the course or Binder.",
               SETTINGS.binder);
      }
    }, SETTINGS.start_bound_s * 1000);
  }

  // ---------------------------------------------------------------- a stop the learner can see
  function showStop(panel) {
    const notebook = panel.content;
    let stopped = -1;
    let highest = -1;
    notebook.widgets.forEach((cell, index) => {
      const count = cell.model.type === "code" ? cell.model.executionCount : null;
      if (count !== null && count > highest) { highest = count; stopped = index; }
    });
    if (stopped < 0) return;
    const cell = notebook.widgets[stopped];
    notebook.activeCellIndex = stopped;
    const message = cell.node.querySelector(
      '.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.stderr"],' +
      '.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.error"]') || cell.node;
    message.scrollIntoView({ block: "center" });
  }

  function watchKernel(panel, kernel) {
    if (!kernel || watched.has(kernel)) return;
    watched.add(kernel);
    const pending = []; // headers of execute requests sent and not yet answered, in order
    kernel.anyMessage.connect((_, args) => {
      const msg = args.msg;
      const type = msg.header.msg_type;
      if (args.direction === "send" && type === "execute_request") {
        pending.push(msg.header);
      } else if (args.direction === "recv" && type === "execute_reply") {
        const at = pending.findIndex((h) => h.msg_id === msg.parent_header.msg_id);
        if (at < 0) return;
        pending.splice(at, 1);
        if (msg.content.status !== "error" || (msg.metadata && msg.metadata.cause === "interrupt")) return;
        // the kernel client cancelled what was queued behind the error: the idle each one was owed
        for (const header of pending.splice(0)) {
          kernel.anyMessage.emit({ direction: "recv", msg: {
            channel: "iopub", header: { ...header, msg_id: header.msg_id + "-aborted", msg_type: "status" },
            parent_header: header, metadata: {}, content: { execution_state: "idle" }, buffers: [] } });
        }
        for (const delay of [150, 600, 1500]) setTimeout(() => showStop(panel), delay);
      }
    });
  }

  function watchPanels() {
    const app = window.jupyterapp;
    if (!app) return;
    for (const widget of app.shell.widgets("main")) {
      const context = widget.sessionContext;
      if (!context || !widget.content || !widget.content.widgets) continue;
      if (context.session) watchKernel(widget, context.session.kernel);
      if (!watched.has(context)) {
        watched.add(context);
        context.kernelChanged.connect((_, change) => watchKernel(widget, change.newValue));
      }
    }
  }

  probeCdn();
  watchStart();
  setInterval(watchPanels, 500);
})();
