//! The Manchester contact benchmark with `railfem contact`'s geometry, side by side with
//! CONTACT's reference numbers: prints the markdown tables of docs/contact-tool.md
//! (geometry and normal load; creepages and creep forces).
//!
//! `cargo run --release --example manchester_contact`

fn main() -> Result<(), railfem::framework::FemError> {
    let rows = railfem::contact_tool::manchester::compare()?;
    print!("{}", railfem::contact_tool::manchester::markdown(&rows));
    println!();
    print!(
        "{}",
        railfem::contact_tool::manchester::creep_markdown(&rows)
    );
    Ok(())
}
