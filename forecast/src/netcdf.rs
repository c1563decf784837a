//! Ocean-model currents and bathymetry from CF-convention NetCDF, read with
//! the pure-Rust `netcdf3` crate (classic and 64-bit-offset formats; NetCDF-4
//! is HDF5 and is refused with what to do: `nccopy -k classic`).
//!
//! Currents: `u`/`v` (or `uo`/`vo`, or any variables whose `standard_name`
//! is `eastward_sea_water_velocity` / `northward_sea_water_velocity`) on
//! time × [depth ×] latitude × longitude, in that order (CF's T, Z, Y, X).
//! With a depth axis the current is averaged over the levels within the
//! glider's depth range (the nearest level when none lies within it).
//! Packed values (`scale_factor`, `add_offset`) and fill values
//! (`_FillValue`, `missing_value`, NaN) are honoured. Bathymetry: GEBCO's
//! `elevation` (metres up, negative at sea) or a `depth`/`z` grid (metres
//! down, or up when its `positive` attribute says so) on latitude ×
//! longitude. Interpolation is linear in time, latitude and longitude; a
//! position or time outside the grid, or next to a missing value (land), is
//! an error that says where and when.

use std::io::Cursor;
use std::path::Path;

use gloc_dbd::header::days_from_civil;
use gloc_engine::files::Limit;
use gloc_sim::navigation::Xy;
use netcdf3::{DataSet, DataType, FileReader};

use crate::currents::CurrentField;
use crate::export::iso_time;

/// The largest NetCDF file read (it is read whole).
pub const NETCDF: Limit = Limit {
    what: "a NetCDF file",
    bytes: 1 << 30,
};

/// A regular grid's axis, increasing.
#[derive(Clone, Debug, PartialEq)]
struct Axis {
    values: Vec<f64>,
}

impl Axis {
    /// The cell `i` and weight `f` with value = values[i]·(1−f) + values[i+1]·f;
    /// `None` outside. One value: inside only at it, `(0, 0)`.
    fn locate(&self, at: f64) -> Option<(usize, f64)> {
        let values = &self.values;
        let (first, last) = (*values.first()?, *values.last()?);
        if !(at >= first && at <= last) {
            return None;
        }
        if values.len() == 1 {
            return Some((0, 0.0));
        }
        let upper = values
            .partition_point(|v| *v <= at)
            .clamp(1, values.len() - 1);
        let (a, b) = (values[upper - 1], values[upper]);
        Some((upper - 1, ((at - a) / (b - a)).clamp(0.0, 1.0)))
    }

    fn span(&self) -> (f64, f64) {
        (
            self.values.first().copied().unwrap_or(f64::NAN),
            self.values.last().copied().unwrap_or(f64::NAN),
        )
    }
}

/// Currents on a grid in time and space.
#[derive(Clone, Debug, PartialEq)]
pub struct GridCurrents {
    pub name: String,
    times: Axis,
    lats: Axis,
    lons: Axis,
    /// Depth-averaged u and v, `[time][lat][lon]`; NaN where missing.
    u: Vec<f64>,
    v: Vec<f64>,
    /// The levels averaged (m), for the description.
    pub levels: Vec<f64>,
}

/// A water-depth grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Bathymetry {
    pub name: String,
    lats: Axis,
    lons: Axis,
    /// Water depth (m, positive down), `[lat][lon]`.
    depth: Vec<f64>,
}

/// A field of water depth.
pub trait DepthField: Send + Sync {
    /// The water depth (m, positive) at decimal degrees; an error off the
    /// grid or on land.
    fn depth_at(&self, time: f64, lat: f64, lon: f64) -> Result<f64, String>;
}

fn open(path: &Path) -> Result<(FileReader, u64), String> {
    let bytes = gloc_engine::files::read(path, NETCDF)
        .map_err(|error| format!("cannot read `{}`: {error}", path.display()))?;
    let length = bytes.len() as u64;
    if bytes.starts_with(b"\x89HDF") {
        return Err(format!(
            "`{}` is NetCDF-4 (HDF5), which this build does not read: convert it to the \
             classic format with `nccopy -k classic IN.nc OUT.nc`",
            path.display()
        ));
    }
    if !bytes.starts_with(b"CDF") {
        return Err(format!(
            "`{}` is not a NetCDF file (it does not begin with `CDF`)",
            path.display()
        ));
    }
    check_header(&bytes).map_err(|problem| {
        format!(
            "`{}`: not a readable NetCDF-3 file: {problem}",
            path.display()
        )
    })?;
    let reader =
        FileReader::open_seek_read(&path.display().to_string(), Box::new(Cursor::new(bytes)))
            .map_err(|error| {
                format!(
                    "`{}`: not a readable NetCDF-3 file: {error:?}",
                    path.display()
                )
            })?;
    Ok((reader, length))
}

/// Walks a classic (CDF-1) or 64-bit-offset (CDF-2) header and checks that every
/// count it declares fits in the bytes that follow, before the `netcdf3` parser
/// sizes its vectors from those counts (a damaged count would otherwise ask for
/// gigabytes and abort the process).
fn check_header(bytes: &[u8]) -> Result<(), String> {
    let mut cursor = HeaderCursor { bytes, at: 0 };
    let offset_bytes = match cursor.take(4)? {
        b"CDF\x01" => 4,
        b"CDF\x02" => 8,
        b"CDF\x05" => {
            return Err(
                "CDF-5 (64-bit data) is not read: convert it with `nccopy -k classic`".to_string(),
            )
        }
        _ => return Err("an unknown NetCDF version".to_string()),
    };
    cursor.word()?; // numrecs
    let tag = cursor.word()?;
    let dims = cursor.count(12)?;
    if !(tag == 0x0A || (tag == 0 && dims == 0)) {
        return Err("byte 8: expected a dimension list".to_string());
    }
    for _ in 0..dims {
        cursor.name()?;
        cursor.word()?;
    }
    cursor.attributes()?;
    let tag = cursor.word()?;
    let vars = cursor.count(16)?;
    if !(tag == 0x0B || (tag == 0 && vars == 0)) {
        return Err(format!("byte {}: expected a variable list", cursor.at - 8));
    }
    for _ in 0..vars {
        cursor.name()?;
        let rank = cursor.count(4)?;
        for _ in 0..rank {
            if cursor.word()? as usize >= dims {
                return Err(format!(
                    "byte {}: a variable names a dimension that does not exist",
                    cursor.at - 4
                ));
            }
        }
        cursor.attributes()?;
        type_size(cursor.word()?)?;
        cursor.word()?; // vsize
        cursor.take(offset_bytes)?; // begin
    }
    Ok(())
}

/// Reads a NetCDF-3 header's words, checking each against what is left.
struct HeaderCursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl HeaderCursor<'_> {
    fn left(&self) -> usize {
        self.bytes.len().saturating_sub(self.at)
    }

    fn take(&mut self, count: usize) -> Result<&[u8], String> {
        if count > self.left() {
            return Err(format!("the header is cut short at byte {}", self.at));
        }
        let slice = &self.bytes[self.at..self.at + count];
        self.at += count;
        Ok(slice)
    }

    fn word(&mut self) -> Result<u32, String> {
        let four = self.take(4)?;
        Ok(u32::from_be_bytes([four[0], four[1], four[2], four[3]]))
    }

    /// A count of items of at least `item` bytes each, which must fit in the file.
    fn count(&mut self, item: usize) -> Result<usize, String> {
        let at = self.at;
        let count = self.word()? as usize;
        if count.saturating_mul(item.max(1)) > self.left() {
            return Err(format!(
                "byte {at}: a count of {count} does not fit in the file"
            ));
        }
        Ok(count)
    }

    fn name(&mut self) -> Result<(), String> {
        let length = self.count(1)?;
        self.take(length.div_ceil(4) * 4).map(|_| ())
    }

    fn attributes(&mut self) -> Result<(), String> {
        let tag = self.word()?;
        let count = self.count(12)?;
        if tag == 0 && count == 0 {
            return Ok(());
        }
        if tag != 0x0C {
            return Err(format!("byte {}: expected an attribute list", self.at - 8));
        }
        for _ in 0..count {
            self.name()?;
            let size = type_size(self.word()?)?;
            let values = self.count(size)?;
            self.take((values * size).div_ceil(4) * 4)?;
        }
        Ok(())
    }
}

fn type_size(code: u32) -> Result<usize, String> {
    match code {
        1 | 2 => Ok(1),
        3 => Ok(2),
        4 | 5 => Ok(4),
        6 => Ok(8),
        other => Err(format!("unknown data type {other}")),
    }
}

/// The first of a NetCDF attribute's numbers, as f64.
fn first<T: Copy + Into<f64>>(values: Option<&[T]>) -> Option<f64> {
    values?.first().map(|&value| value.into())
}

/// A NetCDF variable's numbers, as f64.
fn widen<T: Copy + Into<f64>>(values: Option<&[T]>) -> Option<Vec<f64>> {
    values.map(|values| values.iter().map(|&value| value.into()).collect())
}

/// A variable's values as f64, unpacked, fill values as NaN. Refuses a
/// variable larger than the file (a corrupt header must not allocate more).
fn read_values(
    reader: &mut FileReader,
    file_length: u64,
    name: &str,
    path: &Path,
) -> Result<Vec<f64>, String> {
    let data_set = reader.data_set();
    let variable = data_set
        .get_var(name)
        .ok_or_else(|| format!("`{}`: no variable `{name}`", path.display()))?;
    let element = match variable.data_type() {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 => 2,
        DataType::I32 | DataType::F32 => 4,
        DataType::F64 => 8,
    };
    if (variable.len() as u64).saturating_mul(element) > file_length {
        return Err(format!(
            "`{}`: variable `{name}` claims {} values, more than the file holds",
            path.display(),
            variable.len()
        ));
    }
    let number = |attribute: &str| -> Option<f64> {
        let attr = variable.get_attr(attribute)?;
        first(attr.get_f64())
            .or_else(|| first(attr.get_f32()))
            .or_else(|| first(attr.get_i32()))
            .or_else(|| first(attr.get_i16()))
            .or_else(|| first(attr.get_i8()))
    };
    let fill = number("_FillValue");
    let missing = number("missing_value");
    let scale = number("scale_factor").unwrap_or(1.0);
    let offset = number("add_offset").unwrap_or(0.0);
    let data_type = variable.data_type();
    let data = reader
        .read_var(name)
        .map_err(|error| format!("`{}`: cannot read `{name}`: {error:?}", path.display()))?;
    let raw: Vec<f64> = match data_type {
        DataType::I8 => widen(data.get_i8()),
        DataType::U8 => widen(data.get_u8()),
        DataType::I16 => widen(data.get_i16()),
        DataType::I32 => widen(data.get_i32()),
        DataType::F32 => widen(data.get_f32()),
        DataType::F64 => widen(data.get_f64()),
    }
    .unwrap_or_default();
    Ok(raw
        .into_iter()
        .map(|value| {
            let is_fill = |mark: Option<f64>| {
                mark.is_some_and(|m| {
                    value == m || (m.abs() > 1e30 && value.abs() >= m.abs() * 0.999)
                })
            };
            if !value.is_finite() || is_fill(fill) || is_fill(missing) {
                f64::NAN
            } else {
                value * scale + offset
            }
        })
        .collect())
}

fn attribute_text(data_set: &DataSet, variable: &str, attribute: &str) -> String {
    data_set
        .get_var_attr_as_string(variable, attribute)
        .unwrap_or_default()
        .trim_end_matches('\0')
        .to_string()
}

/// What a coordinate is, from its name, units, `standard_name` and `axis`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Time,
    Depth,
    Lat,
    Lon,
    Other,
}

fn role(data_set: &DataSet, name: &str) -> Role {
    let lower = name.to_ascii_lowercase();
    let units = attribute_text(data_set, name, "units").to_ascii_lowercase();
    let standard = attribute_text(data_set, name, "standard_name").to_ascii_lowercase();
    let axis = attribute_text(data_set, name, "axis").to_ascii_uppercase();
    if axis == "T" || standard == "time" || units.contains(" since ") || lower == "time" {
        Role::Time
    } else if axis == "Y"
        || standard == "latitude"
        || units.starts_with("degrees_n")
        || lower.starts_with("lat")
    {
        Role::Lat
    } else if axis == "X"
        || standard == "longitude"
        || units.starts_with("degrees_e")
        || lower.starts_with("lon")
    {
        Role::Lon
    } else if axis == "Z"
        || standard == "depth"
        || matches!(
            lower.as_str(),
            "depth" | "z" | "lev" | "level" | "deptht" | "depthu"
        )
    {
        Role::Depth
    } else {
        Role::Other
    }
}

/// CF time units (`seconds|minutes|hours|days since YYYY-MM-DD[ HH:MM:SS]`) to
/// a factor and an epoch in Unix seconds.
fn time_units(units: &str) -> Option<(f64, f64)> {
    let (unit, origin) = units.split_once(" since ")?;
    let factor = match unit.trim().to_ascii_lowercase().as_str() {
        "seconds" | "second" | "secs" | "sec" | "s" => 1.0,
        "minutes" | "minute" | "mins" | "min" => 60.0,
        "hours" | "hour" | "hrs" | "hr" | "h" => 3600.0,
        "days" | "day" | "d" => 86_400.0,
        _ => return None,
    };
    let origin = origin
        .trim()
        .trim_end_matches("UTC")
        .trim()
        .trim_end_matches('Z');
    let (date, clock) = origin
        .split_once([' ', 'T'])
        .unwrap_or((origin, "00:00:00"));
    let mut parts = date.split('-').map(|p| p.parse::<i64>().ok());
    let (year, month, day) = (parts.next()??, parts.next()??, parts.next()??);
    let mut clock_parts = clock.split(':').map(|p| p.parse::<f64>().ok());
    let hour = clock_parts.next().flatten().unwrap_or(0.0);
    let minute = clock_parts.next().flatten().unwrap_or(0.0);
    let second = clock_parts.next().flatten().unwrap_or(0.0);
    let epoch = days_from_civil(year, month, day) as f64 * 86_400.0
        + hour * 3600.0
        + minute * 60.0
        + second;
    Some((factor, epoch))
}

/// An increasing axis from a coordinate variable; `reversed` if it was decreasing.
fn axis(values: Vec<f64>, name: &str, path: &Path) -> Result<(Axis, bool), String> {
    if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
        return Err(format!(
            "`{}`: coordinate `{name}` is empty or has missing values",
            path.display()
        ));
    }
    let increasing = values.windows(2).all(|w| w[1] > w[0]);
    let decreasing = values.windows(2).all(|w| w[1] < w[0]);
    match (increasing, decreasing) {
        (true, _) => Ok((Axis { values }, false)),
        (false, true) => {
            let mut values = values;
            values.reverse();
            Ok((Axis { values }, true))
        }
        _ => Err(format!(
            "`{}`: coordinate `{name}` is not monotonic",
            path.display()
        )),
    }
}

fn find_velocity(data_set: &DataSet, standard: &str, names: &[&str]) -> Option<String> {
    let vars = data_set.get_var_names();
    vars.iter()
        .find(|name| attribute_text(data_set, name, "standard_name") == standard)
        .or_else(|| vars.iter().find(|name| names.contains(&name.as_str())))
        .cloned()
}

/// Reads currents; `depth_range` (m) is the glider's, over which a depth axis
/// is averaged (`None`: every level).
pub fn read_currents(path: &Path, depth_range: Option<(f64, f64)>) -> Result<GridCurrents, String> {
    let (mut reader, length) = open(path)?;
    let (u_name, v_name, dims, units, depth_up) = {
        let data_set = reader.data_set();
        let (Some(u_name), Some(v_name)) = (
            find_velocity(
                data_set,
                "eastward_sea_water_velocity",
                &["u", "uo", "U", "water_u"],
            ),
            find_velocity(
                data_set,
                "northward_sea_water_velocity",
                &["v", "vo", "V", "water_v"],
            ),
        ) else {
            return Err(format!(
                "`{}`: no current: give variables `u` and `v` (or with standard_name \
                 eastward_sea_water_velocity / northward_sea_water_velocity)",
                path.display()
            ));
        };
        let dims = data_set
            .get_var(&u_name)
            .map(|v| v.dim_names())
            .unwrap_or_default();
        let v_dims = data_set
            .get_var(&v_name)
            .map(|v| v.dim_names())
            .unwrap_or_default();
        if dims != v_dims {
            return Err(format!(
                "`{}`: `{u_name}` and `{v_name}` have different dimensions",
                path.display()
            ));
        }
        let roles: Vec<Role> = dims.iter().map(|d| role(data_set, d)).collect();
        if !matches!(
            roles.as_slice(),
            [Role::Time, Role::Lat, Role::Lon] | [Role::Time, Role::Depth, Role::Lat, Role::Lon]
        ) {
            return Err(format!(
                "`{}`: `{u_name}` is on ({}): give time × [depth ×] latitude × longitude, in that order",
                path.display(),
                dims.join(", ")
            ));
        }
        let units = attribute_text(data_set, &dims[0], "units");
        let depth_up = dims.len() == 4
            && attribute_text(data_set, &dims[1], "positive").eq_ignore_ascii_case("up");
        (u_name, v_name, dims, units, depth_up)
    };
    let has_depth = dims.len() == 4;
    let coordinate = |reader: &mut FileReader, name: &str| read_values(reader, length, name, path);
    let time_name = &dims[0];
    let (factor, epoch) = time_units(&units).ok_or_else(|| {
        format!(
            "`{}`: time units `{units}`: give `seconds|minutes|hours|days since YYYY-MM-DD hh:mm:ss`",
            path.display()
        )
    })?;
    let raw_times: Vec<f64> = coordinate(&mut reader, time_name)?
        .into_iter()
        .map(|t| epoch + t * factor)
        .collect();
    let (times, times_reversed) = axis(raw_times, time_name, path)?;
    let (lat_name, lon_name) = (&dims[dims.len() - 2], &dims[dims.len() - 1]);
    let (lats, lats_reversed) = axis(coordinate(&mut reader, lat_name)?, lat_name, path)?;
    let (lons, lons_reversed) = axis(coordinate(&mut reader, lon_name)?, lon_name, path)?;
    let levels_all = if has_depth {
        let name = &dims[1];
        let mut values = coordinate(&mut reader, name)?;
        if depth_up {
            values.iter_mut().for_each(|v| *v = -*v);
        }
        values
    } else {
        Vec::new()
    };
    let chosen: Vec<usize> = if has_depth {
        choose_levels(&levels_all, depth_range)
    } else {
        Vec::new()
    };
    let u_raw = read_values(&mut reader, length, &u_name, path)?;
    let v_raw = read_values(&mut reader, length, &v_name, path)?;
    let (nt, ny, nx) = (times.values.len(), lats.values.len(), lons.values.len());
    let nz = levels_all.len().max(1);
    let cells = nt
        .checked_mul(nz)
        .and_then(|n| n.checked_mul(ny))
        .and_then(|n| n.checked_mul(nx));
    if cells != Some(u_raw.len()) || v_raw.len() != u_raw.len() {
        return Err(format!(
            "`{}`: `{u_name}` does not match its dimensions",
            path.display()
        ));
    }
    let mut u = vec![f64::NAN; nt * ny * nx];
    let mut v = vec![f64::NAN; nt * ny * nx];
    for t in 0..nt {
        let source_t = if times_reversed { nt - 1 - t } else { t };
        for y in 0..ny {
            let source_y = if lats_reversed { ny - 1 - y } else { y };
            for x in 0..nx {
                let source_x = if lons_reversed { nx - 1 - x } else { x };
                let at = |z: usize| ((source_t * nz + z) * ny + source_y) * nx + source_x;
                let average = |raw: &[f64]| -> f64 {
                    if !has_depth {
                        return raw[at(0)];
                    }
                    let values: Vec<f64> = chosen
                        .iter()
                        .map(|&z| raw[at(z)])
                        .filter(|v| v.is_finite())
                        .collect();
                    if values.is_empty() {
                        f64::NAN
                    } else {
                        values.iter().sum::<f64>() / values.len() as f64
                    }
                };
                let index = (t * ny + y) * nx + x;
                u[index] = average(&u_raw);
                v[index] = average(&v_raw);
            }
        }
    }
    Ok(GridCurrents {
        name: path.display().to_string(),
        times,
        lats,
        lons,
        u,
        v,
        levels: chosen.iter().map(|&z| levels_all[z]).collect(),
    })
}

/// The levels within `range` (m, positive down), else the nearest to its middle.
fn choose_levels(levels: &[f64], range: Option<(f64, f64)>) -> Vec<usize> {
    let Some((low, high)) = range else {
        return (0..levels.len()).collect();
    };
    let within: Vec<usize> = (0..levels.len())
        .filter(|&z| levels[z] >= low && levels[z] <= high)
        .collect();
    if !within.is_empty() {
        return within;
    }
    let middle = (low + high) / 2.0;
    (0..levels.len())
        .min_by(|&a, &b| {
            (levels[a] - middle)
                .abs()
                .total_cmp(&(levels[b] - middle).abs())
        })
        .into_iter()
        .collect()
}

fn where_and_when(time: Option<f64>, lat: f64, lon: f64) -> String {
    let place = format!(
        "{:.4}° {}, {:.4}° {}",
        lat.abs(),
        if lat < 0.0 { "S" } else { "N" },
        lon.abs(),
        if lon < 0.0 { "W" } else { "E" }
    );
    match time {
        Some(time) => format!("at {} {place}", iso_time(time)),
        None => format!("at {place}"),
    }
}

/// Bilinear interpolation in a `[lat][lon]` slice.
fn bilinear(grid: &[f64], nx: usize, (y, fy): (usize, f64), (x, fx): (usize, f64)) -> f64 {
    let y1 = (y + 1).min(grid.len() / nx.max(1) - 1);
    let x1 = (x + 1).min(nx - 1);
    let at = |yy: usize, xx: usize| grid[yy * nx + xx];
    let weight = |value: f64, w: f64| if w == 0.0 { 0.0 } else { value * w };
    // A zero weight keeps a missing neighbour (NaN) out of the sum.
    weight(at(y, x), (1.0 - fy) * (1.0 - fx))
        + weight(at(y, x1), (1.0 - fy) * fx)
        + weight(at(y1, x), fy * (1.0 - fx))
        + weight(at(y1, x1), fy * fx)
}

impl CurrentField for GridCurrents {
    fn at(&self, time: f64, lat: f64, lon: f64) -> Result<Xy, String> {
        let outside = |what: &str| {
            let (t0, t1) = self.times.span();
            let (y0, y1) = self.lats.span();
            let (x0, x1) = self.lons.span();
            format!(
                "the track leaves the currents of `{}` {}: {what} (the grid covers {} to {}, latitude {y0}..{y1}, longitude {x0}..{x1})",
                self.name,
                where_and_when(Some(time), lat, lon),
                iso_time(t0),
                iso_time(t1)
            )
        };
        let t = self
            .times
            .locate(time)
            .ok_or_else(|| outside("outside its time span"))?;
        let y = self
            .lats
            .locate(lat)
            .ok_or_else(|| outside("outside its latitudes"))?;
        let x = self
            .lons
            .locate(lon)
            .ok_or_else(|| outside("outside its longitudes"))?;
        let (ny, nx) = (self.lats.values.len(), self.lons.values.len());
        let slice = |field: &[f64], step: usize| -> f64 {
            let start = step * ny * nx;
            bilinear(&field[start..start + ny * nx], nx, y, x)
        };
        let t1 = (t.0 + 1).min(self.times.values.len() - 1);
        let mix = |field: &[f64]| {
            let a = slice(field, t.0);
            if t.1 == 0.0 {
                a
            } else {
                a * (1.0 - t.1) + slice(field, t1) * t.1
            }
        };
        let water = Xy::new(mix(&self.u), mix(&self.v));
        if !(water.x.is_finite() && water.y.is_finite()) {
            return Err(format!(
                "the track reaches a cell without currents (land or missing values) in `{}` {}",
                self.name,
                where_and_when(Some(time), lat, lon)
            ));
        }
        Ok(water)
    }
}

/// Reads a bathymetry grid.
pub fn read_bathymetry(path: &Path) -> Result<Bathymetry, String> {
    let (mut reader, length) = open(path)?;
    let (pick, dims, positive, standard) = {
        let data_set = reader.data_set();
        let names = data_set.get_var_names();
        let pick = names
            .iter()
            .find(|n| matches!(n.as_str(), "elevation" | "depth" | "z" | "Band1" | "topo" | "bathymetry"))
            .or_else(|| names.iter().find(|n| data_set.get_var(n).is_some_and(|v| v.num_dims() == 2)))
            .cloned()
            .ok_or_else(|| format!("`{}`: no elevation or depth grid (variables `elevation`, `depth` or `z` on lat × lon)", path.display()))?;
        let dims = data_set
            .get_var(&pick)
            .map(|v| v.dim_names())
            .unwrap_or_default();
        let roles: Vec<Role> = dims.iter().map(|d| role(data_set, d)).collect();
        if roles != [Role::Lat, Role::Lon] {
            return Err(format!(
                "`{}`: `{pick}` is on ({}): give latitude × longitude",
                path.display(),
                dims.join(", ")
            ));
        }
        let positive = attribute_text(data_set, &pick, "positive").to_ascii_lowercase();
        let standard = attribute_text(data_set, &pick, "standard_name").to_ascii_lowercase();
        (pick, dims, positive, standard)
    };
    let (lats, lats_reversed) = axis(
        read_values(&mut reader, length, &dims[0], path)?,
        &dims[0],
        path,
    )?;
    let (lons, lons_reversed) = axis(
        read_values(&mut reader, length, &dims[1], path)?,
        &dims[1],
        path,
    )?;
    let raw = read_values(&mut reader, length, &pick, path)?;
    let (ny, nx) = (lats.values.len(), lons.values.len());
    if ny.checked_mul(nx) != Some(raw.len()) {
        return Err(format!(
            "`{}`: `{pick}` does not match its dimensions",
            path.display()
        ));
    }
    // Elevation (up) unless the grid says it is a depth (down).
    let is_depth =
        positive == "down" || (pick == "depth" && positive != "up") || standard.contains("depth");
    let mut depth = vec![f64::NAN; ny * nx];
    for y in 0..ny {
        let sy = if lats_reversed { ny - 1 - y } else { y };
        for x in 0..nx {
            let sx = if lons_reversed { nx - 1 - x } else { x };
            let value = raw[sy * nx + sx];
            depth[y * nx + x] = if is_depth { value } else { -value };
        }
    }
    Ok(Bathymetry {
        name: path.display().to_string(),
        lats,
        lons,
        depth,
    })
}

impl DepthField for Bathymetry {
    fn depth_at(&self, time: f64, lat: f64, lon: f64) -> Result<f64, String> {
        let outside = || {
            let (y0, y1) = self.lats.span();
            let (x0, x1) = self.lons.span();
            format!(
                "the track leaves the bathymetry of `{}` {} (the grid covers latitude {y0}..{y1}, longitude {x0}..{x1})",
                self.name,
                where_and_when(Some(time), lat, lon)
            )
        };
        let y = self.lats.locate(lat).ok_or_else(outside)?;
        let x = self.lons.locate(lon).ok_or_else(outside)?;
        let depth = bilinear(&self.depth, self.lons.values.len(), y, x);
        if !(depth.is_finite() && depth > 0.0) {
            return Err(format!(
                "the track reaches land or a cell without depth in `{}` {}",
                self.name,
                where_and_when(Some(time), lat, lon)
            ));
        }
        Ok(depth)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cf_time_units_by_hand() {
        assert_eq!(
            time_units("hours since 1970-01-01 00:00:00"),
            Some((3600.0, 0.0))
        );
        // 1950-01-01 is 7,305 days before 1970 (20 years, 5 leap days).
        assert_eq!(
            time_units("days since 1950-01-01"),
            Some((86_400.0, -7305.0 * 86_400.0))
        );
        assert_eq!(
            time_units("seconds since 2019-08-21T13:54:06Z"),
            Some((1.0, 1_566_395_646.0))
        );
        assert_eq!(time_units("fortnights since 2000-01-01"), None);
    }

    #[test]
    fn an_axis_locates_cells_and_refuses_outside() {
        let axis = Axis {
            values: vec![0.0, 1.0, 3.0],
        };
        assert_eq!(axis.locate(2.0), Some((1, 0.5)));
        assert_eq!(axis.locate(3.0), Some((1, 1.0)));
        assert_eq!(axis.locate(0.0), Some((0, 0.0)));
        assert_eq!(axis.locate(-0.1), None);
        assert_eq!(axis.locate(f64::NAN), None);
        assert_eq!(Axis { values: vec![5.0] }.locate(5.0), Some((0, 0.0)));
    }

    #[test]
    fn levels_within_the_range_else_the_nearest() {
        let levels = [0.0, 10.0, 20.0, 100.0];
        assert_eq!(choose_levels(&levels, Some((5.0, 30.0))), vec![1, 2]);
        assert_eq!(choose_levels(&levels, Some((40.0, 50.0))), vec![2]);
        assert_eq!(choose_levels(&levels, None), vec![0, 1, 2, 3]);
    }
}
