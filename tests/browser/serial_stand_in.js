// A stand-in for the Web Serial API, injected into the page before JupyterLab loads (playwright's
// add_init_script). requestPort() returns a port whose streams are a WebSocket to the test's bridge
// (tests/browser/serial_bridge.py: a pty with pymodbus's RTU server behind it). Every chunk each way is
// noted with the page's clock in window.__serialTiming. __BRIDGE_URL__ is replaced by the test.
(() => {
  const BRIDGE = "__BRIDGE_URL__";
  const timing = [];
  window.__serialTiming = timing;
  const hex = (bytes) => Array.from(bytes, (b) => b.toString(16).padStart(2, "0")).join(" ");

  class StandInPort extends EventTarget {
    constructor() {
      super();
      this.readable = null;
      this.writable = null;
      this.ws = null;
    }
    getInfo() { return { usbVendorId: 0x0403, usbProductId: 0x6001 }; }
    async open(options) {
      const query = `baud=${options.baudRate}&parity=${options.parity}&stop=${options.stopBits}` +
        `&data=${options.dataBits}`;
      const ws = new WebSocket(`${BRIDGE}?${query}`);
      ws.binaryType = "arraybuffer";
      await new Promise((resolve, reject) => {
        ws.onopen = resolve;
        ws.onerror = () => reject(new DOMException("the bridge cannot be reached", "NetworkError"));
      });
      this.ws = ws;
      timing.push({ t: performance.now(), dir: "open", options });
      const port = this;
      this.readable = new ReadableStream({
        start(controller) {
          ws.onmessage = (event) => {
            const bytes = new Uint8Array(event.data);
            timing.push({ t: performance.now(), dir: "rx", hex: hex(bytes) });
            controller.enqueue(bytes);
          };
          ws.onclose = () => {
            port.readable = null;
            try { controller.error(new DOMException("The device has been lost.", "NetworkError")); }
            catch (e) { /* already closed */ }
          };
        },
        cancel() { ws.close(); },
      });
      this.writable = new WritableStream({
        write(chunk) {
          timing.push({ t: performance.now(), dir: "tx", hex: hex(chunk) });
          ws.send(chunk);
        },
      });
    }
    async close() {
      if (this.ws) this.ws.close();
      this.readable = null;
      this.writable = null;
      timing.push({ t: performance.now(), dir: "close" });
    }
  }

  const serial = new EventTarget();
  serial.requestPort = async () => new StandInPort();
  serial.getPorts = async () => [];
  Object.defineProperty(Navigator.prototype, "serial", { get() { return serial; }, configurable: true });
})();
