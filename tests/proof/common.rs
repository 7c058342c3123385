//! Shared knobs of the proof: the seed and the sample scale.

/// The base seed: `LIGHTPROOF_SEED` or a fixed default, recorded in every message.
pub fn seed() -> u64 {
    std::env::var("LIGHTPROOF_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x11_9470)
}

/// `LIGHTPROOF_SCALE` (default 1) multiplies every sample count for a deeper proof.
pub fn scale() -> u64 {
    std::env::var("LIGHTPROOF_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&s: &u64| s >= 1)
        .unwrap_or(1)
}
