// Playback clock. While the speech is playing, the <audio> element is the clock
// (time = audio.currentTime), so the body follows the sound even when the audio stalls.
// Without audio (none given, failed to load, or past its end) a performance.now() clock
// carries on from where the audio stopped.

export class Clock {
  constructor(audio, duration) {
    this.audio = audio;
    this.duration = duration;
    this.offset = 0; // seconds, the time while paused
    this.since = 0; // performance.now() at the last (re)start of the fallback clock
    this.playing = false;
    this.audioRunning = false;
    this.audioFailed = !audio || !audio.getAttribute('src');
    if (audio) {
      audio.addEventListener('error', () => {
        this.audioFailed = true;
        this.switchToFallback(this.offset);
      });
      audio.addEventListener('ended', () => this.switchToFallback(audio.currentTime));
    }
  }

  switchToFallback(from) {
    if (!this.audioRunning) return;
    this.audioRunning = false;
    this.offset = from;
    this.since = performance.now();
  }

  time() {
    if (!this.playing) return this.offset;
    if (this.audioRunning) return this.audio.currentTime;
    return Math.min(this.duration, this.offset + (performance.now() - this.since) / 1000);
  }

  audioCovers(t) {
    if (this.audioFailed) return false;
    const length = this.audio.duration;
    return !Number.isFinite(length) || t < length;
  }

  play() {
    if (this.playing) return;
    if (this.offset >= this.duration) this.offset = 0;
    this.playing = true;
    this.since = performance.now();
    if (!this.audioCovers(this.offset)) return;
    this.audio.currentTime = this.offset;
    this.audioRunning = true;
    this.audio.play().catch(() => {
      this.audioFailed = true;
      this.switchToFallback(this.offset);
    });
  }

  pause() {
    if (!this.playing) return;
    this.offset = this.time();
    this.playing = false;
    this.audioRunning = false;
    if (this.audio) this.audio.pause();
  }

  seek(t) {
    const time = Math.min(this.duration, Math.max(0, t));
    this.offset = time;
    this.since = performance.now();
    if (this.audioFailed) return;
    if (this.audioCovers(time)) {
      this.audio.currentTime = time;
      if (this.playing && !this.audioRunning) {
        this.audioRunning = true;
        this.audio.play().catch(() => {});
      }
    } else if (this.audioRunning) {
      this.audio.pause();
      this.audioRunning = false;
    }
  }

  // Call once per frame: stops at the end.
  tick() {
    if (this.playing && this.time() >= this.duration) {
      this.pause();
      this.offset = this.duration;
    }
  }
}
