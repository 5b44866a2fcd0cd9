//! Joins pictures, or crops of them, into one: side by side (`--row`) or one above the other
//! (`--column`), with a white gap between them. `scripts/pictures.sh` makes the comparison
//! pictures in `docs/` with it (without and with, or one close-up per setting).
//!
//! `cargo run --release -p sward --example montage -- --row|--column [--gap PIXELS] --out
//! OUT.png IN.png[@X,Y,W,H]...` — `@X,Y,W,H` keeps the W×H pixels whose top left corner is at
//! (X, Y); without it the whole picture is kept.

use anyhow::{bail, Context, Result};
use image::{imageops, Rgba, RgbaImage};
use std::path::PathBuf;

/// How the pieces are laid out.
#[derive(Clone, Copy, PartialEq)]
enum Layout {
    Row,
    Column,
}

/// One input: a picture and the part of it that is kept.
struct Piece {
    path: PathBuf,
    crop: Option<[u32; 4]>,
}

struct Montage {
    layout: Layout,
    gap: u32,
    out: PathBuf,
    pieces: Vec<Piece>,
}

fn main() {
    if let Err(error) = run() {
        eprintln!("montage: {error:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let montage = parse(std::env::args().skip(1))?;
    let pictures = montage.pieces.iter().map(cut).collect::<Result<Vec<_>>>()?;
    join(&pictures, montage.layout, montage.gap)
        .save(&montage.out)
        .with_context(|| format!("cannot write {}", montage.out.display()))
}

fn parse(args: impl Iterator<Item = String>) -> Result<Montage> {
    const USAGE: &str = "usage: montage --row|--column [--gap PIXELS] --out OUT.png IN.png[@X,Y,W,H]...";
    let mut layout = None;
    let mut gap = 6;
    let mut out = None;
    let mut pieces = Vec::new();
    let mut args = args;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--row" => layout = Some(Layout::Row),
            "--column" => layout = Some(Layout::Column),
            "--gap" => {
                let value = args.next().context("--gap takes a number of pixels")?;
                gap = value
                    .parse()
                    .with_context(|| format!("--gap takes a whole number of pixels, not {value:?}"))?;
            }
            "--out" => out = Some(PathBuf::from(args.next().context("--out takes a path")?)),
            flag if flag.starts_with("--") => bail!("unknown flag {flag}; {USAGE}"),
            piece => pieces.push(parse_piece(piece)?),
        }
    }
    let (Some(layout), Some(out)) = (layout, out) else {
        bail!("a layout (--row or --column) and --out are needed; {USAGE}");
    };
    if pieces.is_empty() {
        bail!("no pictures to join; {USAGE}");
    }
    Ok(Montage {
        layout,
        gap,
        out,
        pieces,
    })
}

/// `IN.png` or `IN.png@X,Y,W,H`.
fn parse_piece(text: &str) -> Result<Piece> {
    let Some((path, crop)) = text.rsplit_once('@') else {
        return Ok(Piece {
            path: text.into(),
            crop: None,
        });
    };
    let numbers = crop
        .split(',')
        .map(str::parse)
        .collect::<Result<Vec<u32>, _>>()
        .ok()
        .filter(|n| n.len() == 4);
    let Some(numbers) = numbers else {
        bail!("{text}: a crop is four whole numbers, @X,Y,WIDTH,HEIGHT");
    };
    Ok(Piece {
        path: path.into(),
        crop: Some([numbers[0], numbers[1], numbers[2], numbers[3]]),
    })
}

/// The piece's picture, cropped.
fn cut(piece: &Piece) -> Result<RgbaImage> {
    let picture = image::open(&piece.path)
        .with_context(|| format!("cannot read the picture {}", piece.path.display()))?
        .to_rgba8();
    crop(piece, picture)
}

/// `picture` cropped as the piece says.
fn crop(piece: &Piece, picture: RgbaImage) -> Result<RgbaImage> {
    let Some([x, y, width, height]) = piece.crop else {
        return Ok(picture);
    };
    let fits = x.checked_add(width).is_some_and(|right| right <= picture.width())
        && y.checked_add(height).is_some_and(|bottom| bottom <= picture.height());
    if !fits || width == 0 || height == 0 {
        bail!(
            "{}: the crop {width}×{height} at ({x}, {y}) is not inside the {}×{} picture",
            piece.path.display(),
            picture.width(),
            picture.height()
        );
    }
    Ok(imageops::crop_imm(&picture, x, y, width, height).to_image())
}

/// The pictures one after another, `gap` white pixels between them; a narrower (or shorter)
/// picture is centred across the row (or column).
fn join(pictures: &[RgbaImage], layout: Layout, gap: u32) -> RgbaImage {
    let along = |p: &RgbaImage| if layout == Layout::Row { p.width() } else { p.height() };
    let across = |p: &RgbaImage| if layout == Layout::Row { p.height() } else { p.width() };
    let length = pictures.iter().map(along).sum::<u32>() + gap * (pictures.len() as u32 - 1);
    let breadth = pictures.iter().map(across).max().unwrap_or(0);
    let (width, height) = match layout {
        Layout::Row => (length, breadth),
        Layout::Column => (breadth, length),
    };
    let mut joined = RgbaImage::from_pixel(width, height, Rgba([255, 255, 255, 255]));
    let mut at = 0;
    for picture in pictures {
        let side = (breadth - across(picture)) / 2;
        let (x, y) = match layout {
            Layout::Row => (at, side),
            Layout::Column => (side, at),
        };
        imageops::replace(&mut joined, picture, x.into(), y.into());
        at += along(picture) + gap;
    }
    joined
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(text: &str) -> impl Iterator<Item = String> + '_ {
        text.split_whitespace().map(str::to_string)
    }

    #[test]
    fn bad_input_is_one_sentence() {
        let said = |text: &str| parse(args(text)).err().unwrap().to_string();
        assert!(said("--out o.png a.png").starts_with("a layout (--row or --column) and --out are needed"));
        assert!(said("--row --out o.png").starts_with("no pictures to join"));
        assert!(said("--row --out o.png a.png@1,2,3").contains("a crop is four whole numbers"));
        assert!(said("--row --sideways").starts_with("unknown flag --sideways"));
        let piece = Piece {
            path: "p.png".into(),
            crop: Some([30, 0, 20, 10]),
        };
        let picture = RgbaImage::new(40, 10);
        let error = crop(&piece, picture).unwrap_err().to_string();
        assert_eq!(
            error,
            "p.png: the crop 20×10 at (30, 0) is not inside the 40×10 picture"
        );
    }

    #[test]
    fn pieces_join_with_a_white_gap_the_narrower_centred() {
        let red = RgbaImage::from_pixel(4, 2, Rgba([255, 0, 0, 255]));
        let blue = RgbaImage::from_pixel(2, 6, Rgba([0, 0, 255, 255]));
        let row = join(&[red.clone(), blue.clone()], Layout::Row, 3);
        assert_eq!(row.dimensions(), (4 + 3 + 2, 6));
        assert_eq!(
            row.get_pixel(0, 2),
            &Rgba([255, 0, 0, 255]),
            "red centred across the row"
        );
        assert_eq!(row.get_pixel(0, 0), &Rgba([255, 255, 255, 255]));
        assert_eq!(row.get_pixel(5, 3), &Rgba([255, 255, 255, 255]), "the gap is white");
        assert_eq!(row.get_pixel(7, 5), &Rgba([0, 0, 255, 255]));
        let column = join(&[red, blue], Layout::Column, 0);
        assert_eq!(column.dimensions(), (4, 8));
        assert_eq!(
            column.get_pixel(1, 2),
            &Rgba([0, 0, 255, 255]),
            "blue centred across the column"
        );
    }
}
