//! A small ELF64 reader that checks a plugin library is whole before `dlopen` maps it.
//!
//! `dlopen` maps a library's loadable segments straight from the file; a library copied
//! only part way then faults with SIGBUS when the loader touches a page past the end of
//! the file. [`check`] reads the headers and refuses, with one line, a file that is not an
//! ELF shared object for this machine or whose program header table, section header table,
//! `PT_LOAD` segments or sections reach past the end of the file. Only fields the check
//! needs are decoded (layout: the System V ABI, "ELF Header", "Program Header", "Section
//! Header"); everything is bounds-checked arithmetic on the bytes, no unsafe code.

/// ELF identification: the magic number.
const MAGIC: [u8; 4] = [0x7f, b'E', b'L', b'F'];
/// `EI_CLASS` of a 64-bit object.
const CLASS_64: u8 = 2;
/// `EI_DATA` of a little-endian object.
const DATA_LSB: u8 = 1;
/// `e_type` of a shared object.
const ET_DYN: u16 = 3;
/// Size of the ELF64 header, a program header and a section header (bytes).
const EHDR_SIZE: usize = 64;
const PHDR_SIZE: usize = 56;
const SHDR_SIZE: usize = 64;
/// `p_type` of a loadable segment.
const PT_LOAD: u32 = 1;
/// `sh_type` of a section that occupies no file space (`.bss`).
const SHT_NOBITS: u32 = 8;

/// `e_machine` of the machine this program runs on, if known.
fn host_machine() -> Option<u16> {
    match std::env::consts::ARCH {
        "x86_64" => Some(62),
        "aarch64" => Some(183),
        "riscv64" => Some(243),
        "powerpc64" => Some(21),
        "s390x" => Some(22),
        "loongarch64" => Some(258),
        _ => None,
    }
}

/// Little-endian field readers over a byte slice; `None` past its end.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn get<const N: usize>(&self, at: u64) -> Option<[u8; N]> {
        let at = usize::try_from(at).ok()?;
        self.0.get(at..at.checked_add(N)?)?.try_into().ok()
    }
    fn u16(&self, at: u64) -> Option<u16> {
        self.get(at).map(u16::from_le_bytes)
    }
    fn u32(&self, at: u64) -> Option<u32> {
        self.get(at).map(u32::from_le_bytes)
    }
    fn u64(&self, at: u64) -> Option<u64> {
        self.get(at).map(u64::from_le_bytes)
    }
}

/// Checks that `data` (the whole file) is a complete 64-bit little-endian ELF shared
/// object for this machine. The error says what is wrong, for a message that also names
/// the file.
pub fn check(data: &[u8]) -> Result<(), String> {
    let b = Bytes(data);
    let len = data.len() as u64;
    if data.len() < 4 || data[..4] != MAGIC {
        return Err("not an ELF file (no \\x7fELF magic number at its start)".into());
    }
    if data.len() < EHDR_SIZE {
        return Err(format!(
            "the file ends after {len} bytes, inside the {EHDR_SIZE}-byte ELF header (truncated)"
        ));
    }
    if data[4] != CLASS_64 {
        return Err(format!(
            "ELF class {} is not 64-bit (2), which this railfem needs",
            data[4]
        ));
    }
    if data[5] != DATA_LSB {
        return Err(format!(
            "ELF data encoding {} is not little-endian (1), which this machine uses",
            data[5]
        ));
    }
    let field = |v: Option<u64>, what: &str| v.ok_or_else(|| format!("cannot read {what}"));
    let e_type = field(b.u16(16).map(u64::from), "e_type")?;
    if e_type != u64::from(ET_DYN) {
        return Err(format!(
            "ELF type {e_type} is not a shared object (3); build the plugin as a cdylib"
        ));
    }
    let machine = field(b.u16(18).map(u64::from), "e_machine")?;
    if let Some(host) = host_machine() {
        if machine != u64::from(host) {
            return Err(format!(
                "built for ELF machine {machine}, not this machine ({host}, {})",
                std::env::consts::ARCH
            ));
        }
    }
    let phoff = field(b.u64(0x20), "e_phoff")?;
    let shoff = field(b.u64(0x28), "e_shoff")?;
    let phentsize = field(b.u16(0x36).map(u64::from), "e_phentsize")?;
    let phnum = field(b.u16(0x38).map(u64::from), "e_phnum")?;
    let shentsize = field(b.u16(0x3a).map(u64::from), "e_shentsize")?;
    let mut shnum = field(b.u16(0x3c).map(u64::from), "e_shnum")?;
    if phnum == 0 {
        return Err("no program headers, nothing to load".into());
    }
    if phentsize != PHDR_SIZE as u64 {
        return Err(format!(
            "program header size {phentsize} is not {PHDR_SIZE} (damaged header)"
        ));
    }
    table_fits(phoff, phnum, PHDR_SIZE as u64, len, "program header table")?;
    for i in 0..phnum {
        let at = phoff + i * PHDR_SIZE as u64;
        if field(b.u32(at).map(u64::from), "p_type")? != u64::from(PT_LOAD) {
            continue;
        }
        let off = field(b.u64(at + 8), "p_offset")?;
        let filesz = field(b.u64(at + 32), "p_filesz")?;
        extent_fits(off, filesz, len, &format!("loadable segment {i}"))?;
    }
    if shoff == 0 {
        return Ok(()); // no section headers: legal for a loader, nothing more to check
    }
    if shentsize != SHDR_SIZE as u64 {
        return Err(format!(
            "section header size {shentsize} is not {SHDR_SIZE} (damaged header)"
        ));
    }
    if shnum == 0 {
        // Extended numbering: the count is in section 0's `sh_size`.
        table_fits(shoff, 1, SHDR_SIZE as u64, len, "section header table")?;
        shnum = field(b.u64(shoff + 32), "the section count")?;
    }
    table_fits(shoff, shnum, SHDR_SIZE as u64, len, "section header table")?;
    for i in 0..shnum {
        let at = shoff + i * SHDR_SIZE as u64;
        if field(b.u32(at + 4).map(u64::from), "sh_type")? == u64::from(SHT_NOBITS) {
            continue;
        }
        let off = field(b.u64(at + 24), "sh_offset")?;
        let size = field(b.u64(at + 32), "sh_size")?;
        extent_fits(off, size, len, &format!("section {i}"))?;
    }
    Ok(())
}

/// A table of `count` entries of `size` bytes at `offset` lies within `len` bytes.
fn table_fits(offset: u64, count: u64, size: u64, len: u64, what: &str) -> Result<(), String> {
    let bytes = count
        .checked_mul(size)
        .ok_or_else(|| format!("the {what} has an impossible size ({count} entries)"))?;
    extent_fits(offset, bytes, len, &format!("the {what}"))
}

/// `[offset, offset + size)` lies within `len` bytes.
fn extent_fits(offset: u64, size: u64, len: u64, what: &str) -> Result<(), String> {
    match offset.checked_add(size) {
        Some(end) if end <= len => Ok(()),
        _ => Err(format!(
            "{what} spans bytes {offset}..{} but the file has only {len} bytes (truncated or damaged)",
            offset as u128 + size as u128
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A minimal ELF64 shared object for this machine: header, one PT_LOAD of the whole
    /// file, and two section headers (null and one of 16 bytes at offset 200).
    fn tiny() -> Vec<u8> {
        let mut d = vec![0u8; 256 + 2 * SHDR_SIZE];
        d[..4].copy_from_slice(&MAGIC);
        d[4] = CLASS_64;
        d[5] = DATA_LSB;
        d[6] = 1;
        d[16..18].copy_from_slice(&ET_DYN.to_le_bytes());
        d[18..20].copy_from_slice(&host_machine().unwrap_or(62).to_le_bytes());
        d[0x20..0x28].copy_from_slice(&64u64.to_le_bytes()); // e_phoff
        d[0x28..0x30].copy_from_slice(&256u64.to_le_bytes()); // e_shoff
        d[0x36..0x38].copy_from_slice(&(PHDR_SIZE as u16).to_le_bytes());
        d[0x38..0x3a].copy_from_slice(&1u16.to_le_bytes());
        d[0x3a..0x3c].copy_from_slice(&(SHDR_SIZE as u16).to_le_bytes());
        d[0x3c..0x3e].copy_from_slice(&2u16.to_le_bytes());
        d[64..68].copy_from_slice(&PT_LOAD.to_le_bytes());
        d[64 + 32..64 + 40].copy_from_slice(&256u64.to_le_bytes()); // p_filesz
        let s1 = 256 + SHDR_SIZE;
        d[s1 + 4..s1 + 8].copy_from_slice(&1u32.to_le_bytes());
        d[s1 + 24..s1 + 32].copy_from_slice(&200u64.to_le_bytes());
        d[s1 + 32..s1 + 40].copy_from_slice(&16u64.to_le_bytes());
        d
    }

    #[test]
    fn a_whole_library_passes_and_every_cut_fails() {
        let d = tiny();
        assert_eq!(check(&d), Ok(()));
        for cut in [0, 3, 10, 63, 64, 100, 200, 255, 300, d.len() - 1] {
            assert!(check(&d[..cut]).is_err(), "cut at {cut} passed");
        }
    }

    #[test]
    fn damaged_fields_are_named() {
        let mut d = tiny();
        d[64 + 32..64 + 40].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(check(&d).unwrap_err().contains("loadable segment 0"));
        let mut d = tiny();
        d[4] = 1;
        assert!(check(&d).unwrap_err().contains("64-bit"));
        let mut d = tiny();
        d[0x3c..0x3e].copy_from_slice(&u16::MAX.to_le_bytes());
        assert!(check(&d).unwrap_err().contains("section header table"));
        let mut d = tiny();
        d[256 + SHDR_SIZE + 24..256 + SHDR_SIZE + 32].copy_from_slice(&1000u64.to_le_bytes());
        assert!(check(&d).unwrap_err().contains("section 1"));
        assert!(check(b"#!/bin/sh\necho hi\n")
            .unwrap_err()
            .contains("not an ELF file"));
    }
}
