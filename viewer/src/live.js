// Live mode (`?live=1`): the page follows a server-sent event stream at ./stream.
//
// The first message describes the body, later ones pose it:
//   {"skeleton": <BVH HIERARCHY text, or [{"name", "parent", "offset": [x, y, z] metres}]>,
//    "timeline": {...same shape as the file mode's timeline...}}
//   {"frame": i, "time": t, "rotations": [x, y, z, w, ... one quaternion per joint],
//    "root": [x, y, z]}
// Quaternions are local (relative to the parent), scalar last, in the skeleton's joint
// order (BVH hierarchy order, end sites excluded); root is in metres. A message with a
// "timeline" alone replaces the timeline.

export function connectLive(url, { onSkeleton, onTimeline, onFrame, onError }) {
  const source = new EventSource(url);
  source.onmessage = (event) => {
    let message;
    try {
      message = JSON.parse(event.data);
    } catch (error) {
      onError(`live stream: message is not JSON (${error.message})`);
      return;
    }
    if (message.skeleton !== undefined) onSkeleton(message.skeleton);
    if (message.timeline !== undefined) onTimeline(message.timeline);
    if (Array.isArray(message.rotations)) onFrame(message);
  };
  source.onerror = () => onError('live stream: connection lost, retrying');
  return source;
}

// Pose `bones` (joint order) from one frame message; root position in metres → scene units.
export function applyFrame(bones, frame, unit) {
  const q = frame.rotations;
  const count = Math.min(bones.length, Math.floor(q.length / 4));
  for (let j = 0; j < count; j += 1) bones[j].quaternion.set(q[4 * j], q[4 * j + 1], q[4 * j + 2], q[4 * j + 3]);
  if (Array.isArray(frame.root) && frame.root.length === 3 && bones.length) {
    bones[0].position.set(frame.root[0] * unit, frame.root[1] * unit, frame.root[2] * unit);
  }
}
