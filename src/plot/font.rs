//! The font compiled into the binary.
use std::sync::OnceLock;

static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
static REGISTERED: OnceLock<bool> = OnceLock::new();

/// The family name charts use.
pub const FAMILY: &str = "sans-serif";

/// Registers the font once per process; `false` if the font data were refused.
pub fn ensure_registered() -> bool {
    *REGISTERED
        .get_or_init(|| plotters::style::register_font(FAMILY, plotters::style::FontStyle::Normal, DEJAVU_SANS).is_ok())
}
