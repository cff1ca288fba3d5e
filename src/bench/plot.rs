//! PNG plots of the benches (plotters), rendered in memory with an embedded font and written
//! atomically. Log axes where the paper used them (build time against triangles).

use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();
/// DejaVu Sans (free licence, `assets/fonts/DejaVuSans.LICENSE`): plots need no system fonts.
const FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

fn init_font() {
    FONT.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES).is_err() {
            log::warn!("the embedded plot font did not load; plots will have no text");
        }
    });
}

/// One named series of (x, y) points.
pub(crate) struct Series {
    /// The name in the legend.
    pub(crate) name: String,
    /// The points, in x order.
    pub(crate) points: Vec<(f64, f64)>,
}

/// A line plot with points; `x_labels` names integer x positions (categorical axes).
pub(crate) struct LinePlot<'a> {
    /// The plot's title.
    pub(crate) title: &'a str,
    /// The x axis's label.
    pub(crate) x_label: &'a str,
    /// The y axis's label.
    pub(crate) y_label: &'a str,
    /// A logarithmic x axis.
    pub(crate) log_x: bool,
    /// A logarithmic y axis.
    pub(crate) log_y: bool,
    /// Names of the integer x positions, for a categorical axis.
    pub(crate) x_labels: Option<&'a [String]>,
}

const SIZE: (u32, u32) = (900, 560);

impl LinePlot<'_> {
    /// Renders `series` and writes a PNG to `path`.
    pub fn write(&self, path: &Path, series: &[Series]) -> Result<(), String> {
        init_font();
        let pts: Vec<(f64, f64)> = series.iter().flat_map(|s| s.points.iter().copied()).filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
        if pts.is_empty() {
            return Err(format!("{}: nothing to plot", path.display()));
        }
        let range = |v: &mut dyn Iterator<Item = f64>, log: bool| {
            let (mut lo, mut hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
            if log {
                lo = lo.max(1e-9) / 1.5;
                hi = hi.max(lo * 10.0) * 1.5;
            } else {
                let pad = ((hi - lo) * 0.08).max(hi.abs() * 0.05).max(1e-9);
                lo = if lo >= 0.0 { (lo - pad).max(0.0) } else { lo - pad };
                hi += pad;
            }
            lo..hi
        };
        let xr = range(&mut pts.iter().map(|p| p.0), self.log_x);
        let yr = range(&mut pts.iter().map(|p| p.1), self.log_y);
        let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
            root.fill(&WHITE).map_err(|e| e.to_string())?;
            let mut builder = ChartBuilder::on(&root);
            builder.caption(self.title, ("sans-serif", 22)).margin(16).x_label_area_size(48).y_label_area_size(72);
            let labels = self.x_labels;
            let fmt_x = move |x: &f64| match labels {
                Some(l) => l.get(x.round() as usize).filter(|_| (x - x.round()).abs() < 1e-6).cloned().unwrap_or_default(),
                None => format!("{x}"),
            };
            macro_rules! draw {
                ($chart:expr) => {{
                    let mut chart = $chart;
                    chart
                        .configure_mesh()
                        .x_desc(self.x_label)
                        .y_desc(self.y_label)
                        .x_label_formatter(&fmt_x)
                        .label_style(("sans-serif", 15))
                        .draw()
                        .map_err(|e| e.to_string())?;
                    for (i, s) in series.iter().enumerate() {
                        let color = Palette99::pick(i).to_rgba();
                        let p: Vec<(f64, f64)> = s.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
                        chart
                            .draw_series(LineSeries::new(p.clone(), color.stroke_width(2)))
                            .map_err(|e| e.to_string())?
                            .label(s.name.clone())
                            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
                        chart.draw_series(p.iter().map(|&(x, y)| Circle::new((x, y), 4, color.filled()))).map_err(|e| e.to_string())?;
                    }
                    chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.8))
                        .border_style(BLACK)
                        .label_font(("sans-serif", 15))
                        .draw()
                        .map_err(|e| e.to_string())?;
                }};
            }
            match (self.log_x, self.log_y) {
                (true, true) => draw!(builder.build_cartesian_2d(xr.log_scale(), yr.log_scale()).map_err(|e| e.to_string())?),
                (true, false) => draw!(builder.build_cartesian_2d(xr.log_scale(), yr).map_err(|e| e.to_string())?),
                (false, true) => draw!(builder.build_cartesian_2d(xr, yr.log_scale()).map_err(|e| e.to_string())?),
                (false, false) => draw!(builder.build_cartesian_2d(xr, yr).map_err(|e| e.to_string())?),
            }
            root.present().map_err(|e| e.to_string())?;
        }
        let img = image::RgbImage::from_raw(SIZE.0, SIZE.1, buf).ok_or("plot buffer size")?;
        let mut png = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).map_err(|e| e.to_string())?;
        crate::util::write_atomic(path, &png).map_err(|e| format!("{}: {e}", path.display()))
    }
}
