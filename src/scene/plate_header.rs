//! What a plate picture is, read from its header alone: PNG or JPEG, its
//! size, and whether the file holds the whole of it. A few dozen bytes and
//! one small read per PNG chunk or JPEG segment header, never the pixels, so
//! `drape check` can vet every file of a long sequence, and a file claiming a
//! picture larger than Drape renders is refused before it is read.

use std::fs::File;
use std::io::{self, Read as _, Seek as _, SeekFrom};
use std::path::Path;

use super::read_capped::open_regular;
use super::validate::MAX_IMAGE_SIDE_PX;
use crate::atomic_file::io_reason;

/// A plate picture's format and size, as its header gives them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlatePicture {
    pub format: PictureFormat,
    pub width_px: u32,
    pub height_px: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureFormat {
    Png,
    Jpeg,
}

impl std::fmt::Display for PlatePicture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let format = match self.format {
            PictureFormat::Png => "PNG",
            PictureFormat::Jpeg => "JPEG",
        };
        write!(f, "{format} {} × {} px", self.width_px, self.height_px)
    }
}

/// Most PNG chunks or JPEG segments walked through looking for the picture
/// data and the file's end; a file with more is taken on trust past them.
const MAX_HEADER_STEPS: u32 = 100_000;

const PNG_SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";
/// The chunk every PNG ends with: no data, its type and its checksum.
const PNG_END_CHUNK: &[u8; 12] = b"\0\0\0\0IEND\xae\x42\x60\x82";

/// The header of the picture at `path`, or what is wrong with it in a
/// user's words: no such file, a folder or a device, too short, neither PNG
/// nor JPEG, a damaged or cut-short header, a kind or size Drape does not
/// decode, a PNG whose chunks run past the end of the file.
pub fn read_plate_header(path: &Path) -> Result<PlatePicture, String> {
    let (mut file, length_bytes) = open_picture(path)?;
    let mut start = [0u8; 33];
    let read = read_up_to(&mut file, &mut start).map_err(|error| format!("cannot read it ({error})"))?;
    let start = &start[..read];
    if start.starts_with(PNG_SIGNATURE) {
        return png_header(&mut file, start, length_bytes);
    }
    if start.starts_with(&[0xFF, 0xD8]) {
        return jpeg_header(&mut file, length_bytes);
    }
    if length_bytes < PNG_SIGNATURE.len() as u64 {
        return Err(format!("the file is {} long: too short for a PNG or JPEG picture", bytes_long(length_bytes)));
    }
    Err("it is not a PNG or JPEG picture (its first bytes are neither's)".to_owned())
}

/// The file at `path` open for reading, with its length, when it is a
/// regular file ([`open_regular`]: a folder, device or FIFO is refused
/// unopened).
fn open_picture(path: &Path) -> Result<(File, u64), String> {
    open_regular(path).map_err(|error| match error.kind() {
        io::ErrorKind::NotFound => "there is no such file".to_owned(),
        _ => io_reason(&error),
    })
}

fn bytes_long(length_bytes: u64) -> String {
    if length_bytes == 1 { "1 byte".to_owned() } else { format!("{length_bytes} bytes") }
}

/// Reads into `buffer` until it is full or the file ends; how many bytes came.
fn read_up_to(file: &mut File, buffer: &mut [u8]) -> io::Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match file.read(&mut buffer[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
    Ok(filled)
}

/// Exactly `N` bytes at `offset`, or `None` where the file ends first.
fn bytes_at<const N: usize>(file: &mut File, offset: u64) -> Result<Option<[u8; N]>, String> {
    let mut buffer = [0u8; N];
    let read = file
        .seek(SeekFrom::Start(offset))
        .and_then(|_| read_up_to(file, &mut buffer))
        .map_err(|error| format!("cannot read it ({error})"))?;
    Ok((read == N).then_some(buffer))
}

/// Refuses a picture with no pixels, or with a side longer than any picture
/// Drape renders: it would only be scaled down, after taking up to four
/// times the memory of the largest render to decode.
fn size_allowed(picture: PlatePicture) -> Result<PlatePicture, String> {
    let (width, height) = (picture.width_px, picture.height_px);
    if width == 0 || height == 0 {
        return Err(format!("its header claims a picture of {width} × {height} pixels, which holds none"));
    }
    if width > MAX_IMAGE_SIDE_PX || height > MAX_IMAGE_SIDE_PX {
        return Err(format!(
            "its header claims {width} × {height} pixels; a plate may be at most {MAX_IMAGE_SIDE_PX} pixels \
             a side, the largest picture Drape renders: scale it down"
        ));
    }
    Ok(picture)
}

/// A PNG's header chunk (`start` holds the file's first 33 bytes or fewer),
/// then its chunks walked by their lengths up to the picture data, and to the
/// end chunk unless the file ends with it.
fn png_header(file: &mut File, start: &[u8], length_bytes: u64) -> Result<PlatePicture, String> {
    let Some(header) = start.get(8..33) else {
        return Err(format!("the PNG is cut short: {} in all, inside its header", bytes_long(length_bytes)));
    };
    let (length, kind, data, checksum) = (&header[..4], &header[4..8], &header[8..21], &header[21..]);
    if length != 13u32.to_be_bytes() || kind != b"IHDR" {
        return Err("not a readable PNG: it does not start with its header chunk (IHDR)".to_owned());
    }
    if crc32fast::hash(&header[4..21]).to_be_bytes() != checksum {
        return Err("not a readable PNG: its header chunk is damaged (its checksum does not match)".to_owned());
    }
    let number = |at: usize| u32::from_be_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]]);
    let (bit_depth, colour_type) = (data[8], data[9]);
    let allowed_depths: &[u8] = match colour_type {
        0 => &[1, 2, 4, 8, 16],
        3 => &[1, 2, 4, 8],
        2 | 4 | 6 => &[8, 16],
        _ => &[],
    };
    if !allowed_depths.contains(&bit_depth) || data[10] != 0 || data[11] != 0 || data[12] > 1 {
        return Err(format!(
            "not a readable PNG: its header is damaged (colour type {colour_type} at {bit_depth} bits, \
             compression {}, filter {}, interlace {})",
            data[10], data[11], data[12]
        ));
    }
    let picture = size_allowed(PlatePicture { format: PictureFormat::Png, width_px: number(0), height_px: number(4) })?;
    png_chunks_whole(file, length_bytes)?;
    Ok(picture)
}

/// Walks a PNG's chunks after its header: picture data (IDAT) must come, and
/// every chunk must lie within the file up to the end chunk (IEND). Once the
/// picture data is found, a file that ends with the end chunk is whole.
fn png_chunks_whole(file: &mut File, length_bytes: u64) -> Result<(), String> {
    let cut_short = |what: String| format!("the PNG is cut short ({} in all): {what}", bytes_long(length_bytes));
    let ends_whole = length_bytes >= 45 && bytes_at::<12>(file, length_bytes - 12)?.as_ref() == Some(PNG_END_CHUNK);
    let mut offset = 33u64;
    let mut seen_data = false;
    for _ in 0..MAX_HEADER_STEPS {
        if seen_data && ends_whole {
            return Ok(());
        }
        let Some(chunk) = bytes_at::<8>(file, offset)? else {
            return Err(cut_short(format!("it ends at byte {offset} without its end chunk (IEND)")));
        };
        let length = u64::from(u32::from_be_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]));
        let kind = &chunk[4..];
        let end = offset + 12 + length;
        if end > length_bytes {
            let name = String::from_utf8_lossy(kind);
            return Err(cut_short(format!("its {:?} chunk at byte {offset} runs past the end", name.as_ref())));
        }
        match kind {
            b"IDAT" => seen_data = true,
            b"IEND" if seen_data => return Ok(()),
            b"IEND" => return Err("not a readable PNG: it holds no picture data (no IDAT chunk)".to_owned()),
            _ => {}
        }
        offset = end;
    }
    Ok(())
}

/// A JPEG's segments walked from its start marker to its picture data (SOS),
/// reading the frame header (SOF) on the way: its kind, precision and size.
fn jpeg_header(file: &mut File, length_bytes: u64) -> Result<PlatePicture, String> {
    let cut_short = |at: u64| {
        format!(
            "the JPEG is cut short ({} in all): it ends at byte {at}, before its picture data",
            bytes_long(length_bytes)
        )
    };
    let mut offset = 2u64;
    let mut picture = None;
    for _ in 0..MAX_HEADER_STEPS {
        let Some([mark, code]) = bytes_at::<2>(file, offset)? else { return Err(cut_short(offset)) };
        if mark != 0xFF {
            return Err(format!("not a readable JPEG: no segment marker at byte {offset}"));
        }
        match code {
            // Fill bytes before a marker, and markers that stand alone.
            0xFF => offset += 1,
            0x01 | 0xD0..=0xD8 => offset += 2,
            0xD9 => return Err(format!("not a readable JPEG: it ends at byte {offset} before its picture data")),
            0xDA => {
                return picture.ok_or_else(|| "not a readable JPEG: it has no frame header (SOF)".to_owned());
            }
            _ => {
                let Some(length) = bytes_at::<2>(file, offset + 2)? else { return Err(cut_short(offset + 2)) };
                let length = u64::from(u16::from_be_bytes(length));
                if length < 2 {
                    return Err(format!("not a readable JPEG: its segment at byte {offset} is damaged"));
                }
                if offset + 2 + length > length_bytes {
                    return Err(cut_short(length_bytes));
                }
                if is_frame_header(code) {
                    if picture.is_some() {
                        return Err("not a readable JPEG: it has two frame headers (SOF)".to_owned());
                    }
                    picture = Some(jpeg_frame(file, code, offset + 4)?);
                }
                offset += 2 + length;
            }
        }
    }
    Err(format!("not a readable JPEG: no picture data among its first {MAX_HEADER_STEPS} segments"))
}

/// SOF0 to SOF15, less the three markers in that range that are no frame headers.
fn is_frame_header(code: u8) -> bool {
    (0xC0..=0xCF).contains(&code) && !matches!(code, 0xC4 | 0xC8 | 0xCC)
}

/// A JPEG frame header (SOF) at `offset`: the kinds and precision the
/// decoder reads, and the picture's size.
fn jpeg_frame(file: &mut File, code: u8, offset: u64) -> Result<PlatePicture, String> {
    let Some([precision, h0, h1, w0, w1, components]) = bytes_at::<6>(file, offset)? else {
        return Err("the JPEG is cut short inside its frame header".to_owned());
    };
    let kind = match code {
        0xC0..=0xC2 => None,
        0xC3 => Some("lossless"),
        0xC5..=0xC7 | 0xCD..=0xCF => Some("hierarchical"),
        _ => Some("arithmetic-coded"),
    };
    if let Some(kind) = kind {
        return Err(format!("it is a {kind} JPEG; Drape reads baseline and progressive ones: save it again as either"));
    }
    if precision != 8 {
        return Err(format!("it is a {precision}-bit JPEG; Drape reads 8-bit ones"));
    }
    if components == 0 {
        return Err("not a readable JPEG: its frame header lists no colour components".to_owned());
    }
    let (width_px, height_px) = (u32::from(u16::from_be_bytes([w0, w1])), u32::from(u16::from_be_bytes([h0, h1])));
    size_allowed(PlatePicture { format: PictureFormat::Jpeg, width_px, height_px })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A whole PNG of `width × height` grey pixels.
    fn png(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Rgba);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&vec![128; (width * height * 4) as usize]).unwrap();
        writer.finish().unwrap();
        bytes
    }

    /// A PNG header claiming `width × height`, then an empty IDAT and IEND.
    fn png_claiming(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = PNG_SIGNATURE.to_vec();
        let mut chunk = |kind: &[u8], data: &[u8]| {
            bytes.extend((data.len() as u32).to_be_bytes());
            let mut body = kind.to_vec();
            body.extend(data);
            bytes.extend(&body);
            bytes.extend(crc32fast::hash(&body).to_be_bytes());
        };
        let mut header = width.to_be_bytes().to_vec();
        header.extend(height.to_be_bytes());
        header.extend([8, 6, 0, 0, 0]);
        chunk(b"IHDR", &header);
        chunk(b"IDAT", &[]);
        chunk(b"IEND", &[]);
        bytes
    }

    /// A JPEG's markers up to its scan: SOI, an APP0 segment, a frame header
    /// of `code` and `width × height`, SOS.
    fn jpeg(code: u8, width: u16, height: u16) -> Vec<u8> {
        let mut bytes = vec![0xFF, 0xD8, 0xFF, 0xE0, 0, 6, b'J', b'F', b'I', b'F'];
        bytes.extend([0xFF, code, 0, 11, 8]);
        bytes.extend(height.to_be_bytes());
        bytes.extend(width.to_be_bytes());
        bytes.extend([1, 1, 0x11, 0]);
        bytes.extend([0xFF, 0xDA, 0, 8, 1, 1, 0, 0, 63, 0, 1, 2, 3, 0xFF, 0xD9]);
        bytes
    }

    fn header_of(bytes: &[u8]) -> Result<PlatePicture, String> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plate");
        std::fs::write(&path, bytes).unwrap();
        read_plate_header(&path)
    }

    #[test]
    fn whole_pictures_give_their_format_and_size() {
        let picture = header_of(&png(7, 3)).unwrap();
        assert_eq!(picture, PlatePicture { format: PictureFormat::Png, width_px: 7, height_px: 3 });
        assert_eq!(picture.to_string(), "PNG 7 × 3 px");
        let mut trailing = png(2, 2);
        trailing.extend(b"bytes after the end chunk");
        assert!(header_of(&trailing).is_ok(), "data after IEND is ignored, as decoders do");
        let jpeg = header_of(&jpeg(0xC2, 640, 480)).unwrap();
        assert_eq!(jpeg, PlatePicture { format: PictureFormat::Jpeg, width_px: 640, height_px: 480 });
    }

    #[test]
    fn what_is_no_picture_says_what_it_is() {
        let error = |bytes: &[u8]| header_of(bytes).unwrap_err();
        assert_eq!(error(b""), "the file is 0 bytes long: too short for a PNG or JPEG picture");
        assert_eq!(error(b"x"), "the file is 1 byte long: too short for a PNG or JPEG picture");
        assert_eq!(
            error(b"GIF89a, a picture Drape does not read"),
            "it is not a PNG or JPEG picture (its first bytes are neither's)"
        );
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read_plate_header(dir.path()).unwrap_err(), "it is a folder, not a regular file");
        assert_eq!(read_plate_header(&dir.path().join("none.png")).unwrap_err(), "there is no such file");
        assert_eq!(read_plate_header(Path::new("/dev/zero")).unwrap_err(), "it is a device, not a regular file");
    }

    #[test]
    fn a_cut_short_or_damaged_png_is_refused() {
        let whole = png(16, 16);
        let cut = header_of(&whole[..whole.len() / 2]).unwrap_err();
        assert!(cut.starts_with("the PNG is cut short") && cut.contains("\"IDAT\" chunk"), "{cut}");
        assert!(header_of(&whole[..20]).unwrap_err().contains("inside its header"));
        let cut_after_data = header_of(&whole[..whole.len() - 12]).unwrap_err();
        assert!(cut_after_data.contains("without its end chunk"), "{cut_after_data}");
        let mut damaged = whole.clone();
        damaged[20] ^= 1;
        assert!(header_of(&damaged).unwrap_err().contains("checksum"));
        let no_data: Vec<u8> = png_claiming(4, 4).iter().copied().take(33).chain(*PNG_END_CHUNK).collect();
        assert!(header_of(&no_data).unwrap_err().contains("no IDAT"));
    }

    #[test]
    fn a_picture_larger_than_drape_renders_is_refused_by_its_header() {
        let huge = header_of(&png_claiming(100_000, 100_000)).unwrap_err();
        assert_eq!(
            huge,
            "its header claims 100000 × 100000 pixels; a plate may be at most 4096 pixels a side, \
             the largest picture Drape renders: scale it down"
        );
        assert!(header_of(&png_claiming(4096, 4096)).is_ok());
        assert!(header_of(&png_claiming(4097, 16)).unwrap_err().contains("4097 × 16"));
        assert!(header_of(&png_claiming(0, 5)).unwrap_err().contains("holds none"));
        assert!(header_of(&jpeg(0xC0, 65_000, 65_000)).unwrap_err().contains("65000 × 65000"));
    }

    #[test]
    fn a_fake_or_unreadable_jpeg_is_refused() {
        let error = |bytes: &[u8]| header_of(bytes).unwrap_err();
        assert!(error(b"\xFF\xD8 this is no JPEG").contains("no segment marker at byte 2"));
        assert!(error(b"\xFF\xD8").contains("cut short"));
        assert!(error(&jpeg(0xC0, 64, 64)[..14]).contains("cut short"));
        assert!(error(&jpeg(0xC3, 64, 64)).contains("lossless JPEG"));
        assert!(error(&jpeg(0xC9, 64, 64)).contains("arithmetic-coded JPEG"));
        assert!(error(b"\xFF\xD8\xFF\xDA\x00\x02").contains("no frame header"));
        assert!(error(b"\xFF\xD8\xFF\xD9").contains("before its picture data"));
    }
}
