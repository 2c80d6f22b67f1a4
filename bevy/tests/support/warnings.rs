//! The WARN events of the process, collected by a global tracing subscriber (the
//! plugin's warnings are asserted on by the tests that include this file).

#![allow(dead_code)]

use std::sync::{Arc, Mutex, OnceLock};

use bevy::log::tracing::{Event, Level, Subscriber, field::Field, field::Visit};
use bevy::log::tracing_subscriber::layer::{Context, Layer, SubscriberExt};
use bevy::log::tracing_subscriber::registry::Registry;

/// Collects the messages of WARN events.
#[derive(Clone, Default)]
pub struct Warnings(Arc<Mutex<Vec<String>>>);

struct Message(String);

impl Visit for Message {
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        if field.name() == "message" {
            self.0 = format!("{value:?}");
        }
    }
}

impl<S: Subscriber> Layer<S> for Warnings {
    fn on_event(&self, event: &Event<'_>, _: Context<'_, S>) {
        if *event.metadata().level() == Level::WARN {
            let mut message = Message(String::new());
            event.record(&mut message);
            self.0.lock().unwrap().push(message.0);
        }
    }
}

/// The process's collector, installed as the global subscriber on the first call.
pub fn warnings() -> &'static Warnings {
    static WARNINGS: OnceLock<Warnings> = OnceLock::new();
    WARNINGS.get_or_init(|| {
        let w = Warnings::default();
        bevy::log::tracing::subscriber::set_global_default(Registry::default().with(w.clone()))
            .expect("the first subscriber");
        w
    })
}

/// The WARN messages so far that mention volfog, in order.
pub fn volfog_warnings() -> Vec<String> {
    warnings()
        .0
        .lock()
        .unwrap()
        .iter()
        .filter(|m| m.contains("volfog"))
        .cloned()
        .collect()
}
