//! `coug poke [MISSION.moos] [--host H] [--port N] VAR=VALUE...`: post values like uPokeDB.
//!
//! `VAR=VALUE` posts a double when VALUE is numeric, else a string; `VAR:=VALUE` always posts
//! a string. A value in double quotes is a string, posted with its quotes as uPokeDB does
//! (recorded traffic: `QNUM="42"` arrives as the 4-character string `"42"`).

use anyhow::bail;
use clap::Args;
use moosdb::Value;

use super::db::{ConnectArgs, connect, split_mission};

/// Arguments of `coug poke`.
#[derive(Debug, Args)]
pub struct PokeArgs {
    /// An optional mission file (first argument ending in `.moos`), then `VAR=VALUE` pairs.
    #[arg(required = true, value_name = "[MISSION.moos] VAR=VALUE")]
    pub items: Vec<String>,
    /// Where the DB is.
    #[command(flatten)]
    pub connect: ConnectArgs,
}

/// One parsed `VAR=VALUE`.
#[derive(Debug, Clone, PartialEq)]
pub struct Poke {
    /// Variable name.
    pub var: String,
    /// Value to post.
    pub value: Value,
}

/// Parses `VAR=VALUE` / `VAR:=VALUE`.
pub fn parse_poke(arg: &str) -> anyhow::Result<Poke> {
    let Some((var, value)) = moos_types::text::parse_poke(arg) else {
        bail!("`{arg}` is not VAR=VALUE");
    };
    if var.is_empty() || var.contains(char::is_whitespace) {
        bail!("`{arg}`: bad variable name");
    }
    Ok(Poke {
        var: var.to_string(),
        value,
    })
}

/// Connects, posts every value, flushes and exits.
pub fn run(args: &PokeArgs) -> anyhow::Result<()> {
    let (mission, rest) = split_mission(&args.items);
    let pokes: Vec<Poke> = rest
        .iter()
        .map(|a| parse_poke(a))
        .collect::<Result<_, _>>()?;
    if pokes.is_empty() {
        bail!("nothing to poke: give VAR=VALUE arguments");
    }
    let name = format!("coug_poke_{}", std::process::id());
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let (client, _mail) = connect(&name, mission.as_deref(), &args.connect).await?;
        for p in &pokes {
            client.notify(&p.var, p.value.clone())?;
            match &p.value {
                Value::Double(d) => outln!("{} = {d} (double)", p.var),
                Value::String(s) => {
                    outln!("{} = {} (string)", p.var, s)
                }
                Value::Binary(b) => outln!("{} = <{} bytes> (binary)", p.var, b.len()),
            }
        }
        client.close().await;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_doubles_unless_quoted_or_forced() {
        assert_eq!(parse_poke("FOO=3.5").unwrap().value, Value::Double(3.5));
        assert_eq!(parse_poke("BAR=hello").unwrap().value, Value::from("hello"));
        assert_eq!(parse_poke("NUMSTR:=2.5").unwrap().value, Value::from("2.5"));
        assert_eq!(
            parse_poke("QNUM=\"42\"").unwrap().value,
            Value::from("\"42\"")
        );
        // uPokeDB's `isNumber` has no exponent: a string, as there.
        assert_eq!(parse_poke("X=-1e3").unwrap().value, Value::from("-1e3"));
        assert_eq!(parse_poke("X=nan").unwrap().value, Value::from("nan"));
        let p = parse_poke("DEPLOY=true").unwrap();
        assert_eq!(p.var, "DEPLOY");
        assert_eq!(p.value, Value::from("true"));
        assert_eq!(
            parse_poke("WPT=points=1,2:3,4").unwrap().value,
            Value::from("points=1,2:3,4")
        );
        assert!(parse_poke("novalue").is_err());
        assert!(parse_poke("=3").is_err());
    }

    #[test]
    fn pokes_reach_an_embedded_db_with_the_right_types() {
        use moosdb::{DataType, Server, ServerConfig};
        let rt = tokio::runtime::Runtime::new().unwrap();
        let server = rt
            .block_on(Server::bind(ServerConfig::with_addr(
                ([127, 0, 0, 1], 0).into(),
            )))
            .unwrap();
        let args = PokeArgs {
            items: ["FOO=3.5", "BAR=hello", "QNUM=\"42\"", "NUMSTR:=2.5"]
                .map(String::from)
                .to_vec(),
            connect: ConnectArgs {
                host: Some("127.0.0.1".into()),
                port: Some(server.local_addr().port()),
                timeout: 10.0,
            },
        };
        run(&args).unwrap();
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while server.with_db(|db| db.current("NUMSTR").is_none()) {
            assert!(std::time::Instant::now() < deadline, "pokes never arrived");
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let got = |k: &str| server.with_db(|db| db.current(k)).unwrap();
        assert_eq!(
            (got("FOO").data_type, got("FOO").dval),
            (DataType::Double, 3.5)
        );
        assert_eq!(got("BAR").sval_str(), "hello");
        assert_eq!(got("QNUM").sval_str(), "\"42\"");
        assert_eq!(
            (got("NUMSTR").data_type, got("NUMSTR").sval_str().as_ref()),
            (DataType::String, "2.5")
        );
        assert!(got("FOO").src_str().starts_with("coug_poke_"));
    }

    #[test]
    fn leading_mission_file_is_split_off() {
        let items = vec!["a.moos".to_string(), "X=1".to_string()];
        let (m, rest) = split_mission(&items);
        assert_eq!(m, Some(std::path::PathBuf::from("a.moos")));
        assert_eq!(rest, &items[1..]);
        let items = vec!["X=1".to_string()];
        assert_eq!(split_mission(&items).0, None);
    }
}
