use super::Outcome;
use super::args::{SrciArgs, SrciCommand};
use crate::srci;

pub fn run(args: SrciArgs) -> anyhow::Result<Outcome> {
    match args.command {
        SrciCommand::Decode { word } => {
            let d = srci::decode(srci::parse_word(&word)?);
            println!("RaStatusWord {} (0x{:08X})", d.word, d.word);
            for f in &d.fields {
                let bits = if f.field.width() == 1 {
                    format!("{}", f.field.bit)
                } else {
                    format!("{}-{}", f.field.bit, f.field.bit + f.field.width() - 1)
                };
                println!("  bit {bits:<5} {:<25} {}", f.field.name, f);
            }
            if d.reserved != 0 {
                eprintln!(
                    "warning: reserved bits 19-31 are set (0x{:08X}); they should be zero",
                    d.reserved
                );
            }
            Ok(Outcome::Success)
        }
        SrciCommand::Encode { fields } => {
            let w = srci::encode(&fields)?;
            println!("{w} (0x{w:08X})");
            Ok(Outcome::Success)
        }
    }
}
