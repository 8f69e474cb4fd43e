// The page's look, injected once so the bundle is the whole viewer.
export const CSS = `
html, body { margin: 0; background: #101317; color: #dfe3ea; font: 14px/1.4 system-ui, sans-serif; }
#mura-app { max-width: 1100px; margin: 0 auto; padding: 8px 12px 24px; }
#mura-app h1 { font-size: 16px; font-weight: 600; margin: 4px 0 8px; }
#mura-stage { position: relative; width: 100%; height: 560px; border-radius: 6px; overflow: hidden; background: #20252c; }
#mura-stage canvas { display: block; width: 100%; height: 100%; }
#mura-status { position: absolute; left: 8px; bottom: 6px; font-size: 12px; color: #aab; }
#mura-controls { display: flex; align-items: center; gap: 10px; margin: 8px 0; }
#mura-controls button { min-width: 64px; padding: 4px 10px; background: #2f3945; color: #fff; border: 1px solid #4a5866; border-radius: 4px; cursor: pointer; }
#mura-scrub { flex: 1; }
#mura-time { font-variant-numeric: tabular-nums; min-width: 120px; text-align: right; }
#mura-views { display: inline-flex; gap: 4px; }
#mura-views button { min-width: 52px; }
#mura-views button.active { background: #4a6a8a; }
#mura-legend { display: flex; flex-wrap: wrap; gap: 4px 12px; margin: 6px 0 2px; font-size: 12px; color: #b8bec8; }
.mura-legend-item { display: inline-flex; align-items: center; gap: 4px; }
.mura-legend-item i { display: inline-block; width: 12px; height: 10px; border-radius: 2px; }
#mura-timeline-strip { display: block; width: 100%; border-radius: 4px; cursor: crosshair; }
#mura-timeline-list h3 { font-size: 13px; margin: 12px 0 4px; color: #aab4c2; }
#mura-timeline-list ol, #mura-timeline-list ul { margin: 0; padding-left: 22px; }
#mura-timeline-list li.active { color: #ffd27f; }
#mura-timeline-list p { margin: 0; font-size: 12px; color: #b8bec8; }
#mura-corpus-panel { margin: 8px 0; }
#mura-search { width: 60%; padding: 4px 8px; background: #1a1f26; color: #dfe3ea; border: 1px solid #4a5866; border-radius: 4px; }
#mura-count { margin-left: 10px; font-size: 12px; color: #aab4c2; }
#mura-items { max-height: 240px; overflow-y: auto; margin: 6px 0; padding-left: 28px; columns: 3 180px; font-size: 13px; }
#mura-items li { cursor: pointer; }
#mura-items li.failed { color: #6b7380; cursor: default; text-decoration: line-through; }
#mura-items li.active { color: #ffd27f; }
#mura-more { font-size: 12px; color: #aab4c2; margin: 0; }
#mura-play-all { font-size: 12px; white-space: nowrap; }
#mura-send { display: flex; gap: 8px; margin: 8px 0; }
#mura-send textarea { flex: 1; background: #1a1f26; color: #dfe3ea; border: 1px solid #4a5866; border-radius: 4px; font: 12px/1.3 monospace; }
`;
