// Live: the page follows a running pipeline through live_bridge, which forwards the processes'
// LCM messages as JSON over a websocket (docs/json_schema.md, "live messages"). Reconnects
// after a second when the bridge goes away.

/**
 * Connects to `url` and calls handlers.open(), handlers.message(object) for every message and
 * handlers.close() when the connection ends (then tries again).
 */
export function connectLive(url, handlers) {
  let socket = null;
  const open = () => {
    socket = new WebSocket(url);
    socket.addEventListener('open', () => handlers.open());
    socket.addEventListener('message', (event) => {
      let message;
      try {
        message = JSON.parse(event.data);
      } catch {
        console.warn(`live: a message that is not JSON (${String(event.data).slice(0, 80)})`);
        return;
      }
      handlers.message(message);
    });
    socket.addEventListener('close', () => {
      handlers.close();
      setTimeout(open, 1000);
    });
  };
  open();
  return { close: () => socket && socket.close() };
}
