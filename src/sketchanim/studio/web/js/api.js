// @ts-check
/** Requests to the studio's JSON API (`/api/...`): answers, and the server's words for a refusal. */

/**
 * The server's words for a refused request: its JSON `detail`, or the status.
 * @param {Response} response
 * @returns {Promise<string>}
 */
export async function refusal(response) {
  try {
    const body = await response.json();
    if (typeof body.detail === 'string') return body.detail;
  } catch { /* not JSON: the status says it */ }
  return `the server answered ${response.status} ${response.statusText}`;
}

/**
 * The JSON a request answers, or an Error with the server's words for a refusal.
 * @param {string} url
 * @param {RequestInit} [init]
 * @returns {Promise<any>}
 */
export async function fetchJson(url, init) {
  const response = await fetch(url, init);
  if (!response.ok) throw new Error(await refusal(response));
  return response.json();
}

/** @param {unknown} err @returns {string} */
export function reason(err) {
  return err instanceof Error ? err.message : String(err);
}
