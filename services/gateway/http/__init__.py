"""The HTTP door: the REST API (`api`, `app`, `routes`), its OpenAPI document, the topic
WebSocket (`ws`) and the dashboard; `api` turns port errors into HTTP answers (one table, `api.STATUS`)."""
