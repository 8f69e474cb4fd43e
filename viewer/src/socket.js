// The page as a client of `mura serve` (`?live=ws`): it opens a WebSocket to the server
// that served it, asks to observe every block with frames, and follows the same skeleton
// and frame messages as live.js's event stream. Feedback messages (prediction,
// blockProgress, syncPointProgress, warning, error) go to onFeedback; send(xml) sends a BML
// block in the protocol's envelope ({"type": "bml", "xml": ...}).

export function socketUrl(location) {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${scheme}//${location.host}/`;
}

export function connectSocket(url, { onSkeleton, onTimeline, onFrame, onFeedback, onError }) {
  const socket = new WebSocket(url);
  socket.onopen = () => socket.send(JSON.stringify({ type: 'observe', frames: true }));
  socket.onmessage = (event) => {
    let message;
    try {
      message = JSON.parse(event.data);
    } catch (error) {
      onError(`realizer: message is not JSON (${error.message})`);
      return;
    }
    if (message.skeleton !== undefined) onSkeleton(message.skeleton);
    else if (message.timeline !== undefined) onTimeline(message.timeline);
    else if (Array.isArray(message.rotations)) onFrame(message);
    else if (typeof message.type === 'string') onFeedback(message);
  };
  socket.onclose = () => onError('realizer: connection closed');
  return {
    send(xml) {
      if (socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify({ type: 'bml', xml }));
    },
  };
}

// One line of text for a feedback message, or null for those not worth showing.
export function describeFeedback(message) {
  switch (message.type) {
    case 'blockProgress':
      return `${message.block}: ${message.point}${message.status ? ` (${message.status})` : ''}`;
    case 'syncPointProgress':
      return `${message.block}: ${message.behavior}:${message.sync} at ${message.time.toFixed(2)} s`;
    case 'warning':
    case 'error':
      return `${message.type}: ${message.where ? `${message.where}: ` : ''}${message.message}`;
    default:
      return null;
  }
}
