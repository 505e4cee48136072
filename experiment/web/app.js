// Placeholder: the browser client (branch web-client) replaces this file.
"use strict";
document.getElementById("app").textContent = "The session client is not built yet.";
